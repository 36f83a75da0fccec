// Rows of grid points (or cells) as bits, 64 to a word, as both the CPU marching cubes and the
// choice of blocks keep them: point x of a row at bit x + 1, so bit 0 and the bits past the row's
// end stand for the padding around the grid (outside, 0).
#pragma once
#include <cstddef>
#include <cstdint>

namespace isoatlas::extract {

using Word = std::uint64_t;
inline constexpr std::size_t kWordBits = 64;

// Words per row of a grid `points` wide: room for the padding at both ends and one bit more, so a
// row can be read one place on (fromNext) up to its last padding bit.
inline std::size_t rowWords(std::int64_t points) { return (std::size_t(points) + 2 + kWordBits) / kWordBits; }

inline unsigned bitAt(const Word* row, std::size_t i) { return unsigned(row[i / kWordBits] >> (i % kWordBits)) & 1u; }
// Bits i and i + 1 of a row (bit i + 1 within it) as bits 0 and 1.
inline unsigned twoBitsAt(const Word* row, std::size_t i) {
  const std::size_t w = i / kWordBits, b = i % kWordBits;
  const Word bits = b + 1 < kWordBits ? row[w] >> b : row[w] >> b | row[w + 1] << 1;
  return unsigned(bits) & 3u;
}
// Word w of a row of `words` words with every bit taken from the next place: bit i holds bit i + 1.
inline Word fromNext(const Word* row, std::size_t w, std::size_t words) {
  return row[w] >> 1 | (w + 1 < words ? row[w + 1] << 63 : 0);
}
// ... from the place before: bit i holds bit i - 1.
inline Word fromPrevious(const Word* row, std::size_t w) { return row[w] << 1 | (w ? row[w - 1] >> 63 : 0); }
inline int lowestBit(Word w) { return __builtin_ctzll(w); }
// The bits lo .. hi of word w (lo <= hi).
inline Word bitRange(std::size_t lo, std::size_t hi, std::size_t w) {
  const std::size_t first = w * kWordBits, last = first + kWordBits - 1;
  if (hi < first || lo > last) return 0;
  const Word fromLo = lo <= first ? ~Word(0) : ~Word(0) << (lo - first);
  const Word toHi = hi >= last ? ~Word(0) : ~Word(0) >> (last - hi);
  return fromLo & toHi;
}

// Which of the n values lie above iso (inside), value x at bit x + 1, into `out` (`words` words: at
// least rowWords(n); the padding bits 0). SSE2 compares four at a time where the compiler has it.
void insideBits(const float* values, std::size_t n, float iso, Word* out, std::size_t words);

}  // namespace isoatlas::extract
