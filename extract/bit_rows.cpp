#include "extract/bit_rows.h"

#include <algorithm>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace isoatlas::extract {

void insideBits(const float* values, std::size_t n, float iso, Word* out, std::size_t words) {
  std::fill(out, out + words, Word(0));
  std::size_t x = 0;  // value x at bit x first, all moved one place up at the end
#if defined(__SSE2__)
  const __m128 level = _mm_set1_ps(iso);
  for (; x + kWordBits <= n; x += kWordBits) {  // a word at a time, gathered in a register
    Word word = 0;
    for (std::size_t k = 0; k < kWordBits; k += 4)
      word |= Word(_mm_movemask_ps(_mm_cmpgt_ps(_mm_loadu_ps(values + x + k), level))) << k;
    out[x / kWordBits] = word;
  }
  for (; x + 4 <= n; x += 4)  // x % 4 == 0: the four bits fall in one word
    out[x / kWordBits] |= Word(_mm_movemask_ps(_mm_cmpgt_ps(_mm_loadu_ps(values + x), level))) << (x % kWordBits);
#endif
  for (; x < n; ++x) out[x / kWordBits] |= Word(values[x] > iso) << (x % kWordBits);
  for (std::size_t w = words; w-- > 0;) out[w] = fromPrevious(out, w);
}

}  // namespace isoatlas::extract
