#include "extract/cpu_marching_cubes.h"

#include "extract/bit_rows.h"
#include "extract/case_table.h"
#include "extract/straddling_blocks.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <limits>

#include "core/cpu_dispatch.h"
#include "core/error.h"
#include "core/huge_pages.h"

namespace isoatlas::extract {
namespace {

constexpr float kOffCorner = 1e-3f;  // crossing points stay this far (in voxels) from grid points

// The corners (cell edges) of a polygon's triangles fanned from its apex, three a triangle, in the
// cycle's order, which is the outward orientation.
template <class Corner>
void forEachApexFanCorner(const Polygon& polygon, const Corner& corner) {
  const std::size_t n = polygon.edges.size(), a = std::size_t(polygon.apex);
  for (std::size_t k = 1; k + 1 < n; ++k)
    for (std::size_t j : {a, (a + k) % n, (a + k + 1) % n}) corner(polygon.edges[j]);
}

// Grid points run from -1 to dims on each axis (the padding included), cells from -1 to dims - 1
// (a cell is named by its lower corner). A row is the points (or cells) of one (y, z), x fastest;
// rows are numbered like points, so cell row (y, z) and point row (y, z) share an index. Rows are
// kept as bits (point or cell x at bit x + 1): which points are inside, which cells are visited, and
// per point row three planes, one per axis, of the edges from its points that get a vertex.
//
// Three passes over rows, each row on its own (so in parallel), and no search:
//   1. count: per point row, its edge planes and their vertices before each word; per cell row, the
//      triangles and centre vertices of its cells;
//   2. exclusive sums over the rows: where each row's vertices, triangles and centres start;
//   3. emit: each row's vertices, then its cells' triangles. A vertex's index is its row's start
//      plus the vertices before it in the row: its word's start and the bits below it in the planes.
// So vertices come in (point, axis) order, centre vertices after them in cell order, triangles in
// cell order (the GPU path numbers the same way within each block, block by block).
//
// The passes that count bits are compiled for popcnt too (core/cpu_dispatch.h).
class RowMarcher {
public:
  RowMarcher(const Grid& grid, float iso, int blockSize, const VisitBlock& visitBlock)
      : grid_(grid), iso_(iso), block_(blockSize), d_(grid.dims), px_(d_[0] + 2), py_(d_[1] + 2), pz_(d_[2] + 2),
        rows_(std::size_t(py_ * pz_)), words_(rowWords(d_[0])), zeros_(words_, 0), visitBlock_(visitBlock) {
    for (int a = 0; a < 3; ++a) blocks_[a] = blockCount(d_[a], blockSize);
    fanCases();
  }

  MarchingResult run() {
    chooseBlocks();
    const RowStarts starts = countRows();
    MarchingResult result;
    result.mesh = emitRows(starts);
    result.cellsVisited = cellsVisited();
    return result;
  }

private:
  // Where each row's vertices, triangles and centre vertices start (the totals last).
  struct RowStarts {
    std::vector<std::uint64_t> edges, triangles, centres;
  };

  // Passes 1 and 2: each row's edge planes and counts, then their exclusive sums.
  RowStarts countRows() {
    // Every word of these is written by the count pass: no zeroing first.
    planes_ = makeHugePageArray<Word>(rows_ * 3 * words_);
    wordStart_ = makeHugePageArray<std::uint32_t>(rows_ * words_);
    RowStarts s{std::vector<std::uint64_t>(rows_ + 1, 0), std::vector<std::uint64_t>(rows_ + 1, 0),
                std::vector<std::uint64_t>(rows_ + 1, 0)};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rows_), [&](const auto& range) {
      std::vector<Word> scratch;
      for (std::size_t r = range.begin(); r != range.end(); ++r)
        countRow(r, scratch, s.edges[r + 1], s.triangles[r + 1], s.centres[r + 1]);
    });
    for (std::size_t r = 0; r < rows_; ++r) {
      s.edges[r + 1] += s.edges[r];
      s.triangles[r + 1] += s.triangles[r];
      s.centres[r + 1] += s.centres[r];
    }
    // Summed in 64 bits and checked before anything is written: a mesh indexes with 32.
    if (s.edges[rows_] + s.centres[rows_] > std::numeric_limits<std::uint32_t>::max() ||
        3 * s.triangles[rows_] > std::numeric_limits<std::uint32_t>::max())
      throw Error("the surface has too many vertices or triangles for one mesh (2^32 indices)", ErrorKind::Failure);
    return s;
  }

  // Pass 3: the mesh, each row's vertices and triangles where the starts say.
  Mesh emitRows(const RowStarts& s) const {
    Mesh mesh;
    const std::uint64_t edgeVertices = s.edges[rows_];
    // Each array is zeroed as it is sized: the three side by side, each marked for huge pages first
    // (when 4 MiB or more), since each is then written whole.
    auto sizeInHugePages = [](auto& array, std::uint64_t n) {
      reserveForHugePages(array, std::size_t(n));
      array.resize(std::size_t(n));
    };
    tbb::parallel_invoke([&] { sizeInHugePages(mesh.positions, edgeVertices + s.centres[rows_]); },
                         [&] { sizeInHugePages(mesh.faceVertices, s.triangles[rows_] * 3); },
                         [&] { sizeInHugePages(mesh.faceOffsets, s.triangles[rows_] + 1); });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rows_), [&](const auto& range) {
      std::vector<Word> scratch;
      for (std::size_t r = range.begin(); r != range.end(); ++r) {
        emitVertices(r, s.edges[r], mesh);
        if (s.triangles[r + 1] > s.triangles[r]) emitTriangles(r, scratch, s.edges, s.triangles[r], edgeVertices + s.centres[r], mesh);
      }
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.faceOffsets.size()), [&](const auto& range) {
      for (std::size_t t = range.begin(); t != range.end(); ++t) mesh.faceOffsets[t] = std::uint32_t(3 * t);
    });
    return mesh;
  }

  std::size_t blockIndex(std::int64_t bx, std::int64_t by, std::int64_t bz) const {
    return std::size_t((bz * blocks_[1] + by) * blocks_[0] + bx);
  }
  // Cells -1 .. B-2 are block 0, B-1 .. 2B-2 block 1, and so on.
  std::int64_t blockOf(std::int64_t cell) const { return (cell + 1) / block_; }
  std::int64_t rowY(std::size_t r) const { return std::int64_t(r % std::size_t(py_)) - 1; }
  std::int64_t rowZ(std::size_t r) const { return std::int64_t(r / std::size_t(py_)) - 1; }
  std::size_t rowOf(std::int64_t y, std::int64_t z) const { return std::size_t((z + 1) * py_ + y + 1); }

  // Per case: its triangles and centre vertices, the edges it crosses, its triangles fanned.
  void fanCases() {
    const auto& table = caseTable();
    for (int c = 0; c < 256; ++c) {
      FannedCase& fanned = fanned_[c];
      for (const Polygon& polygon : table.polygons[std::size_t(c)]) {
        caseTriangles_[c] += std::uint32_t(polygon.apex >= 0 ? polygon.edges.size() - 2 : polygon.edges.size());
        caseCentres_[c] += polygon.apex < 0;
        for (std::int8_t e : polygon.edges) fanned.edges |= std::uint16_t(1u << e);
        if (polygon.apex >= 0) forEachApexFanCorner(polygon, [&](std::int8_t e) { fanned.corners[fanned.cornerCount++] = e; });
      }
    }
  }

  // The blocks to visit and the points' inside bits: the caller's blocks, and the bits of the rows
  // their cells touch; or every row's bits, and the blocks that straddle iso from them.
  void chooseBlocks() {
    if (visitBlock_) {
      visited_.resize(std::size_t(blocks_[0] * blocks_[1] * blocks_[2]));
      tbb::parallel_for(std::int64_t(0), blocks_[2], [&](std::int64_t bz) {
        for (std::int64_t by = 0; by < blocks_[1]; ++by)
          for (std::int64_t bx = 0; bx < blocks_[0]; ++bx) visited_[blockIndex(bx, by, bz)] = visitBlock_(bx, by, bz);
      });
      markCells();
      markInside(false);
    } else {
      markInside(true);
      visited_ = straddlingBlockTable(d_, int(block_), [&](std::int64_t y, std::int64_t z, std::vector<Word>&) { return insideRow(y, z); });
      markCells();
    }
  }

  // Per row of blocks, the cells of a cell row that lie in visited blocks; none when no block of the
  // row is visited.
  void markCells() {
    const std::size_t blockRows = std::size_t(blocks_[1] * blocks_[2]);
    cellMasks_.assign(blockRows * words_, 0);
    blockRowVisited_.assign(blockRows, 0);
    for (std::size_t row = 0; row < blockRows; ++row) {
      Word* mask = cellMasks_.data() + row * words_;
      for (std::int64_t bx = 0; bx < blocks_[0]; ++bx) {
        if (!visited_[row * std::size_t(blocks_[0]) + std::size_t(bx)]) continue;
        blockRowVisited_[row] = 1;
        const BlockCells cells = blockCells(bx, int(block_), d_[0]);
        for (std::int64_t x = cells.first; x <= cells.last; ++x) mask[std::size_t(x + 1) / kWordBits] |= Word(1) << std::size_t(x + 1) % kWordBits;
      }
    }
  }
  const Word* cellRow(std::int64_t y, std::int64_t z) const {
    if (y < -1 || y >= d_[1] || z < -1 || z >= d_[2]) return nullptr;
    const std::size_t row = std::size_t(blockOf(z) * blocks_[1] + blockOf(y));
    return blockRowVisited_[row] ? cellMasks_.data() + row * words_ : nullptr;
  }
  // Whether point row (y, z) is a corner row of a visited cell: the only rows the passes read.
  bool rowNeeded(std::int64_t y, std::int64_t z) const {
    return cellRow(y, z) || cellRow(y - 1, z) || cellRow(y, z - 1) || cellRow(y - 1, z - 1);
  }

  // Inside is value > iso; points in the padding are outside. Unless everyRow, the rows no visited
  // cell touches are left 0.
  void markInside(bool everyRow) {
    inside_ = makeHugePageArray<Word>(rows_ * words_);
    const float iso = iso_;
    tbb::parallel_for(std::int64_t(-1), d_[2] + 1, [&](std::int64_t z) {
      std::vector<float> scratch;
      for (std::int64_t y = -1; y <= d_[1]; ++y) {
        Word* out = inside_.get() + rowOf(y, z) * words_;
        if (y < 0 || y >= d_[1] || z < 0 || z >= d_[2] || !(everyRow || rowNeeded(y, z))) std::fill(out, out + words_, Word(0));
        else insideBits(grid_.row(y, z, scratch), std::size_t(d_[0]), iso, out, words_);
      }
    });
  }
  const Word* insideRow(std::size_t row) const { return inside_.get() + row * words_; }
  const Word* insideRow(std::int64_t y, std::int64_t z) const {
    return y < -1 || y > d_[1] || z < -1 || z > d_[2] ? zeros_.data() : insideRow(rowOf(y, z));
  }
  Word* plane(std::size_t row, int axis) const { return planes_.get() + (row * 3 + std::size_t(axis)) * words_; }

  // The point rows at the corners of cell row r's cells: k = dy + 2 dz for the corner at (y + dy, z + dz).
  std::array<std::size_t, 4> cornerRows(std::size_t r) const {
    return {r, r + 1, r + std::size_t(py_), r + std::size_t(py_) + 1};
  }
  // The cells of cell row r with corners on both sides of iso, in visited blocks: into `out`.
  void crossedCells(std::size_t r, const Word* visited, std::vector<Word>& out) const {
    const auto rows = cornerRows(r);
    const Word *in0 = insideRow(rows[0]), *in1 = insideRow(rows[1]), *in2 = insideRow(rows[2]), *in3 = insideRow(rows[3]);
    out.resize(3 * words_);
    Word *any = out.data() + words_, *all = any + words_;
    for (std::size_t w = 0; w < words_; ++w) any[w] = in0[w] | in1[w] | in2[w] | in3[w], all[w] = in0[w] & in1[w] & in2[w] & in3[w];
    for (std::size_t w = 0; w < words_; ++w)
      out[w] = (any[w] | fromNext(any, w, words_)) & ~(all[w] & fromNext(all, w, words_)) & visited[w];
  }
  // The case of cell i (x = i - 1) of cell row r: corner k in point row k >> 1 of the four, at x + (k & 1).
  int cellCase(std::size_t r, std::size_t i) const {
    const auto rows = cornerRows(r);
    int c = 0;
    for (int k = 0; k < 4; ++k) c |= int(twoBitsAt(insideRow(rows[k]), i) << (2 * k));
    return c;
  }

  // Pass 1 for row r: its edge planes, its vertices before each word, its cells' triangles and
  // centres. An edge that crosses gets a vertex when one of the four cells around it is visited
  // (those cells exist: a crossing edge has an end inside the grid).
  ISOATLAS_CLONES("popcnt")
  void countRow(std::size_t r, std::vector<Word>& scratch, std::uint64_t& edges, std::uint64_t& triangles,
                std::uint64_t& centres) const {
    const std::int64_t y = rowY(r), z = rowZ(r);
    Word *alongX = plane(r, 0), *alongY = plane(r, 1), *alongZ = plane(r, 2);
    std::uint32_t* start = wordStart_.get() + r * words_;
    // The cells around this row's edges: cell rows (y, z), (y-1, z), (y, z-1), (y-1, z-1).
    const Word* cells[4] = {cellRow(y, z), cellRow(y - 1, z), cellRow(y, z - 1), cellRow(y - 1, z - 1)};
    if (!cells[0] && !cells[1] && !cells[2] && !cells[3]) {
      std::fill(alongX, alongX + 3 * words_, Word(0));
      std::fill(start, start + words_, 0u);
      return;
    }
    const Word* visitedHere = cells[0];
    for (const Word*& c : cells) c = c ? c : zeros_.data();
    const Word *in0 = insideRow(r), *in1 = insideRow(y + 1, z), *in2 = insideRow(y, z + 1);
    std::uint32_t count = 0;
    for (std::size_t w = 0; w < words_; ++w) {
      const Word here = in0[w], c0 = cells[0][w], c1 = cells[1][w], c2 = cells[2][w];
      const Word c0Before = fromPrevious(cells[0], w), c1Before = fromPrevious(cells[1], w),
                 c2Before = fromPrevious(cells[2], w);  // cell x - 1 at x
      alongX[w] = (here ^ fromNext(in0, w, words_)) & (c0 | c1 | c2 | cells[3][w]);
      alongY[w] = (here ^ in1[w]) & (c0 | c0Before | c2 | c2Before);
      alongZ[w] = (here ^ in2[w]) & (c0 | c0Before | c1 | c1Before);
      start[w] = count;
      count += std::uint32_t(__builtin_popcountll(alongX[w]) + __builtin_popcountll(alongY[w]) + __builtin_popcountll(alongZ[w]));
    }
    edges = count;
    if (!visitedHere) return;
    crossedCells(r, visitedHere, scratch);
    for (std::size_t w = 0; w < words_; ++w)
      for (Word bits = scratch[w]; bits; bits &= bits - 1) {
        const int c = cellCase(r, w * kWordBits + std::size_t(lowestBit(bits)));
        triangles += caseTriangles_[c];
        centres += caseCentres_[c];
      }
  }

  // Samples outside the grid mirror the nearest grid value about iso when it is inside, so the
  // padded field is outside there and a border surface sits half a voxel past the last voxel.
  float sample(std::int64_t x, std::int64_t y, std::int64_t z) const {
    const std::int64_t cx = std::clamp<std::int64_t>(x, 0, d_[0] - 1), cy = std::clamp<std::int64_t>(y, 0, d_[1] - 1),
                       cz = std::clamp<std::int64_t>(z, 0, d_[2] - 1);
    const float v = grid_.at(cx, cy, cz);
    if (cx == x && cy == y && cz == z) return v;
    return v > iso_ ? 2 * iso_ - v : v;
  }
  // The crossing on the edge from grid point (x, y, z) along axis.
  Vec3 edgePoint(std::int64_t x, std::int64_t y, std::int64_t z, int axis) const {
    const std::int64_t to[3] = {x + (axis == 0), y + (axis == 1), z + (axis == 2)};
    float a, b;
    if (grid_.values && x >= 0 && y >= 0 && z >= 0 && to[0] < d_[0] && to[1] < d_[1] && to[2] < d_[2]) {
      const std::size_t at = std::size_t((z * d_[1] + y) * d_[0] + x);  // both ends in the grid: read them directly
      a = grid_.values[at];
      b = grid_.values[at + std::size_t(axis == 0 ? 1 : axis == 1 ? d_[0] : d_[0] * d_[1])];
    } else {
      a = sample(x, y, z);
      b = sample(to[0], to[1], to[2]);
    }
    const float t = std::clamp((iso_ - a) / (b - a), kOffCorner, 1 - kOffCorner);
    Vec3 p{double(x), double(y), double(z)};
    p[axis] += double(t);
    return p;
  }

  // Pass 3: row r's vertices, in (x, axis) order, numbered from `first`.
  void emitVertices(std::size_t r, std::uint64_t first, Mesh& mesh) const {
    const Word* along[3] = {plane(r, 0), plane(r, 1), plane(r, 2)};
    const std::int64_t y = rowY(r), z = rowZ(r);
    for (std::size_t w = 0; w < words_; ++w)
      for (Word bits = along[0][w] | along[1][w] | along[2][w]; bits; bits &= bits - 1) {
        const std::size_t b = std::size_t(lowestBit(bits));
        const std::int64_t x = std::int64_t(w * kWordBits + b) - 1;
        for (int axis = 0; axis < 3; ++axis)
          if (along[axis][w] >> b & 1) mesh.positions[first++] = edgePoint(x, y, z, axis);
      }
  }

  // How a point row's vertices are numbered: its three edge planes (one after the other), the
  // vertices before each word, the index of its first.
  struct RowNumbers {
    const Word* planes;
    const std::uint32_t* wordStart;
    std::uint64_t first;
  };
  RowNumbers rowNumbers(std::size_t row, const std::vector<std::uint64_t>& edgeStart) const {
    return {plane(row, 0), wordStart_.get() + row * words_, edgeStart[row]};
  }
  // The index of the vertex on the edge from point i of a row along axis (the edge has one).
  std::uint32_t vertexIndex(const RowNumbers& row, std::size_t i, int axis) const {
    const std::size_t w = i / kWordBits, b = i % kWordBits;
    const Word alongX = row.planes[w], alongY = row.planes[words_ + w], alongZ = row.planes[2 * words_ + w];
    const Word below = (Word(1) << b) - 1;
    std::uint64_t index = row.first + row.wordStart[w] + std::uint64_t(__builtin_popcountll(alongX & below)) +
                          std::uint64_t(__builtin_popcountll(alongY & below) + __builtin_popcountll(alongZ & below));
    if (axis > 0) index += alongX >> b & 1;
    if (axis > 1) index += alongY >> b & 1;
    return std::uint32_t(index);  // run() checked that indices fit
  }

  // Pass 3: cell row r's triangles from `triangle`, its centre vertices from `centre`.
  ISOATLAS_CLONES("popcnt")
  void emitTriangles(std::size_t r, std::vector<Word>& scratch, const std::vector<std::uint64_t>& edgeStart,
                     std::uint64_t triangle, std::uint64_t centre, Mesh& mesh) const {
    const std::int64_t y = rowY(r), z = rowZ(r);
    const auto corners = cornerRows(r);
    RowNumbers rows[4]{};
    for (int k = 0; k < 4; ++k) rows[k] = rowNumbers(corners[std::size_t(k)], edgeStart);
    crossedCells(r, cellRow(y, z), scratch);  // the row is visited: it has triangles
    std::uint32_t* out = mesh.faceVertices.data() + std::size_t(triangle) * 3;
    for (std::size_t w = 0; w < words_; ++w)
      for (Word bits = scratch[w]; bits; bits &= bits - 1) {
        const std::size_t i = w * kWordBits + std::size_t(lowestBit(bits));
        const std::int64_t x = std::int64_t(i) - 1;
        const int c = cellCase(r, i);
        std::uint32_t ids[12];
        for (unsigned edges = fanned_[c].edges; edges; edges &= edges - 1) {
          const int e = __builtin_ctz(edges), a = kEdgeCorner[e][0];  // the edge runs from corner a along its axis
          ids[e] = vertexIndex(rows[(a >> 1) & 3], i + std::size_t(a & 1), kEdgeAxis[e]);
        }
        if (!caseCentres_[c]) {
          for (int k = 0; k < fanned_[c].cornerCount; ++k) *out++ = ids[fanned_[c].corners[k]];
        } else {
          out = emitPolygons(c, {x, y, z}, ids, out, centre, mesh);
        }
      }
  }

  // Case c's polygons in cell `cell`, as triangles from `out` (returned past them), each fanned from
  // its apex or from a centre vertex of its own, numbered from `centre` on (advanced past them).
  std::uint32_t* emitPolygons(int c, const std::array<std::int64_t, 3>& cell, const std::uint32_t (&ids)[12], std::uint32_t* out,
                              std::uint64_t& centre, Mesh& mesh) const {
    for (const Polygon& polygon : caseTable().polygons[std::size_t(c)]) {
      const auto& cycle = polygon.edges;
      const std::size_t n = cycle.size();
      if (polygon.apex >= 0) {
        forEachApexFanCorner(polygon, [&](std::int8_t e) { *out++ = ids[e]; });
        continue;
      }
      // A centre vertex of this polygon alone, at the mean of its crossings.
      Vec3 mean{0, 0, 0};
      for (std::int8_t e : cycle) {
        const int a = kEdgeCorner[e][0];
        mean = mean + edgePoint(cell[0] + (a & 1), cell[1] + ((a >> 1) & 1), cell[2] + ((a >> 2) & 1), kEdgeAxis[e]);
      }
      mesh.positions[centre] = mean * (1.0 / double(n));
      for (std::size_t k = 0; k < n; ++k)
        for (std::uint32_t id : {std::uint32_t(centre), ids[cycle[k]], ids[cycle[(k + 1) % n]]}) *out++ = id;
      ++centre;
    }
    return out;
  }

  std::int64_t cellsVisited() const {
    std::int64_t cells = 0;
    auto extent = [&](std::int64_t b, int axis) {
      const BlockCells cells = blockCells(b, int(block_), d_[axis]);
      return cells.last - cells.first + 1;
    };
    for (std::int64_t bz = 0; bz < blocks_[2]; ++bz)
      for (std::int64_t by = 0; by < blocks_[1]; ++by)
        for (std::int64_t bx = 0; bx < blocks_[0]; ++bx)
          if (visited_[blockIndex(bx, by, bz)]) cells += extent(bx, 0) * extent(by, 1) * extent(bz, 2);
    return cells;
  }

  const Grid& grid_;
  const float iso_;
  const std::int64_t block_;
  const std::array<std::int64_t, 3> d_;
  const std::int64_t px_, py_, pz_;  // points per axis, the padding included
  const std::size_t rows_, words_;   // words_: per row of bits, with room for bit px_ (always 0)
  const std::vector<Word> zeros_;    // a row of outside points, or of unvisited cells
  std::int64_t blocks_[3];
  const VisitBlock& visitBlock_;
  std::vector<char> visited_;                         // per block of cells
  std::vector<Word> cellMasks_;                       // per row of blocks (markCells)
  std::vector<std::uint8_t> blockRowVisited_;
  // Written whole by each run, so marked for huge pages when 4 MiB or more (core/huge_pages.h).
  HugePageArray<Word> inside_;                        // per point row (markInside)
  HugePageArray<Word> planes_;                        // per point row: the x, y and z planes (countRow)
  HugePageArray<std::uint32_t> wordStart_;            // per point row and word: the row's vertices before it
  std::uint32_t caseTriangles_[256] = {}, caseCentres_[256] = {};
  // Per case: the cell edges its polygons cross, and, when it has no centre vertex, its triangles
  // fanned from their apexes, three edges each, in the order the polygons give them.
  struct FannedCase {
    std::uint16_t edges = 0;
    int cornerCount = 0;
    std::int8_t corners[36] = {};
  };
  FannedCase fanned_[256];
};

}  // namespace

MarchingResult marchingCubesCpu(const Grid& grid, float iso, int blockSize, const VisitBlock& visitBlock) {
  return RowMarcher(grid, iso, blockSize, visitBlock).run();
}

}  // namespace isoatlas::extract
