#include "extract/straddling_blocks.h"

#include <tbb/parallel_for.h>

#include <memory>

#include "core/error.h"

namespace isoatlas::extract {

std::vector<char> straddlingBlockTable(const std::array<std::int64_t, 3>& d, int blockSize, const InsideRow& insideRow) {
  const std::array<std::int64_t, 3> blocks{blockCount(d[0], blockSize), blockCount(d[1], blockSize), blockCount(d[2], blockSize)};
  const std::size_t words = rowWords(d[0]);
  std::vector<char> straddles(std::size_t(blocks[0] * blocks[1] * blocks[2]), 0);
  // By rows of blocks: the corner points of a row's cells, some inside in `any`, all inside in
  // `all` (a row of padding has none); then each block's stretch of them.
  tbb::parallel_for(std::int64_t(0), blocks[1] * blocks[2], [&](std::int64_t blockRow) {
    const BlockCells ys = blockCells(blockRow % blocks[1], blockSize, d[1]), zs = blockCells(blockRow / blocks[1], blockSize, d[2]);
    std::vector<Word> scratch(words), any(words, 0), all(words, ~Word(0));
    for (std::int64_t z = zs.first; z <= zs.last + 1; ++z)
      for (std::int64_t y = ys.first; y <= ys.last + 1; ++y) {
        if (y < 0 || y >= d[1] || z < 0 || z >= d[2]) {
          std::fill(all.begin(), all.end(), Word(0));
          continue;
        }
        const Word* row = insideRow(y, z, scratch);
        for (std::size_t w = 0; w < words; ++w) any[w] |= row[w], all[w] &= row[w];
      }
    for (std::int64_t bx = 0; bx < blocks[0]; ++bx) {
      const BlockCells xs = blockCells(bx, blockSize, d[0]);
      const std::size_t lo = std::size_t(xs.first + 1), hi = std::size_t(xs.last + 2);  // points first .. last + 1
      bool someInside = false, allInside = true;
      for (std::size_t w = lo / kWordBits; w <= hi / kWordBits; ++w) {
        const Word mask = bitRange(lo, hi, w);
        someInside |= (any[w] & mask) != 0;
        allInside &= (all[w] & mask) == mask;
      }
      straddles[std::size_t(blockRow * blocks[0] + bx)] = someInside && !allInside;
    }
  });
  return straddles;
}

VisitBlock straddlingBlocks(const Grid& grid, float iso, int blockSize) {
  require(grid.values != nullptr, "straddlingBlocks: the grid must hold dense values");
  const auto d = grid.dims;
  const std::size_t words = rowWords(d[0]);
  auto table = std::make_shared<const std::vector<char>>(
      straddlingBlockTable(d, blockSize, [&](std::int64_t y, std::int64_t z, std::vector<Word>& scratch) {
        insideBits(grid.values + std::size_t((z * d[1] + y) * d[0]), std::size_t(d[0]), iso, scratch.data(), words);
        return scratch.data();
      }));
  const std::int64_t bx = blockCount(d[0], blockSize), by = blockCount(d[1], blockSize);
  return [table, bx, by](std::int64_t x, std::int64_t y, std::int64_t z) { return (*table)[std::size_t((z * by + y) * bx + x)] != 0; };
}

}  // namespace isoatlas::extract
