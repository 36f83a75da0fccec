// straddlingBlocks: the blocks of cells whose corners lie on both sides of iso, the padding around
// the grid counted outside: the only blocks with surface (blocks as marching_cubes.h numbers them).
#pragma once
#include <array>
#include <functional>
#include <vector>

#include "extract/bit_rows.h"
#include "extract/marching_cubes.h"

namespace isoatlas::extract {

// From dense values (grid.values), in one pass over them.
VisitBlock straddlingBlocks(const Grid& grid, float iso, int blockSize);

// The same as a table (per block, x fastest: 1 where it straddles), from rows of inside bits
// (bit_rows.h): insideRow(y, z, scratch) gives grid row (y, z)'s, in scratch or elsewhere.
using InsideRow = std::function<const Word*(std::int64_t y, std::int64_t z, std::vector<Word>& scratch)>;
std::vector<char> straddlingBlockTable(const std::array<std::int64_t, 3>& dims, int blockSize, const InsideRow& insideRow);

}  // namespace isoatlas::extract
