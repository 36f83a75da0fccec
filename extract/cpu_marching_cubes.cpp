#include "extract/cpu_marching_cubes.h"

#include "extract/case_table.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <limits>

#include "core/error.h"

namespace isoatlas::extract {
namespace {

constexpr float kOffCorner = 1e-3f;  // crossing points stay this far (in voxels) from grid points

// The vertices a point's 3 edge bits name (std::popcount is a library call without -mpopcnt).
std::uint32_t edgeCount(unsigned bits) { return (0x3221'2110u >> (4 * bits)) & 0xf; }

// A cell's case from its two sides' columns (bit j of a column: the point in row j of the four
// around the cell row): corner k sits in row k >> 1, at x + (k & 1).
int cellCase(unsigned side, unsigned nextSide) {
  constexpr std::uint8_t kSpread[16] = {0x00, 0x01, 0x04, 0x05, 0x10, 0x11, 0x14, 0x15,
                                        0x40, 0x41, 0x44, 0x45, 0x50, 0x51, 0x54, 0x55};  // bit j -> bit 2j
  return kSpread[side] | kSpread[nextSide] << 1;
}

// Grid points run from -1 to dims on each axis (the padding included), cells from -1 to dims - 1
// (a cell is named by its lower corner). A row is the points (or cells) of one (y, z), x fastest;
// rows are numbered like points, so cell row (y, z) and point row (y, z) share an index. Within a
// row, point or cell x sits at x + 1.
//
// Three passes over rows, each row on its own (so in parallel), and no search:
//   1. count: per point, which of its three edges (to x+1, y+1, z+1) cross iso next to a visited
//      cell (3 bits, kept); per row, those edges and the triangles and centre vertices of its cells;
//   2. exclusive sums over the rows: where each row's vertices, triangles and centres start;
//   3. emit: each row's vertices, then its cells' triangles. A vertex's index is its row's start
//      plus the vertices before it in the row, counted while walking the four point rows a cell
//      row touches.
// So vertices come in (point, axis) order, centre vertices after them in cell order, triangles in
// cell order (the GPU path numbers the same way within each block, block by block).
class RowMarcher {
public:
  RowMarcher(const Grid& grid, float iso, int blockSize, const std::function<bool(std::int64_t, std::int64_t, std::int64_t)>& visitBlock)
      : grid_(grid), iso_(iso), block_(blockSize), d_(grid.dims), px_(d_[0] + 2), py_(d_[1] + 2), pz_(d_[2] + 2),
        rows_(std::size_t(py_ * pz_)), zeros_(std::size_t(px_) + 2, 0) {
    for (int a = 0; a < 3; ++a) blocks_[a] = blockCount(d_[a], blockSize);
    visited_.assign(std::size_t(blocks_[0] * blocks_[1] * blocks_[2]), 1);
    if (visitBlock)
      tbb::parallel_for(std::int64_t(0), blocks_[2], [&](std::int64_t bz) {
        for (std::int64_t by = 0; by < blocks_[1]; ++by)
          for (std::int64_t bx = 0; bx < blocks_[0]; ++bx) visited_[blockIndex(bx, by, bz)] = visitBlock(bx, by, bz);
      });
    const auto& table = caseTable();
    for (int c = 0; c < 256; ++c)
      for (const Polygon& polygon : table.polygons[std::size_t(c)]) {
        caseTriangles_[c] += std::uint32_t(polygon.apex >= 0 ? polygon.edges.size() - 2 : polygon.edges.size());
        caseCentres_[c] += polygon.apex < 0;
      }
  }

  MarchingResult run() {
    markCells();
    markInside();
    flags_.assign(std::size_t(px_) * rows_, 0);
    std::vector<std::uint64_t> edgeStart(rows_ + 1, 0), triangleStart(rows_ + 1, 0), centreStart(rows_ + 1, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rows_), [&](const auto& range) {
      std::vector<std::uint8_t> column;
      for (std::size_t r = range.begin(); r != range.end(); ++r)
        countRow(r, column, edgeStart[r + 1], triangleStart[r + 1], centreStart[r + 1]);
    });
    for (std::size_t r = 0; r < rows_; ++r) {
      edgeStart[r + 1] += edgeStart[r];
      triangleStart[r + 1] += triangleStart[r];
      centreStart[r + 1] += centreStart[r];
    }
    // Summed in 64 bits and checked before anything is written: a mesh indexes with 32.
    const std::uint64_t edgeVertices = edgeStart[rows_];
    if (edgeVertices + centreStart[rows_] > std::numeric_limits<std::uint32_t>::max() ||
        3 * triangleStart[rows_] > std::numeric_limits<std::uint32_t>::max())
      throw Error("the surface has too many vertices or triangles for one mesh (2^32 indices)", ErrorKind::Failure);
    MarchingResult result;
    Mesh& mesh = result.mesh;
    mesh.positions.resize(std::size_t(edgeVertices) + centreStart[rows_]);
    mesh.faceVertices.resize(std::size_t(triangleStart[rows_]) * 3);
    mesh.faceOffsets.resize(std::size_t(triangleStart[rows_]) + 1);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rows_), [&](const auto& range) {
      std::vector<std::uint8_t> column, vertexAt;
      for (std::size_t r = range.begin(); r != range.end(); ++r) {
        emitVertices(r, edgeStart[r], edgeStart[r + 1], mesh);
        if (triangleStart[r + 1] > triangleStart[r])
          emitTriangles(r, column, vertexAt, edgeStart, triangleStart[r], edgeVertices + centreStart[r], mesh);
      }
    });
    for (std::size_t t = 0; t < mesh.faceOffsets.size(); ++t) mesh.faceOffsets[t] = std::uint32_t(3 * t);
    result.cellsVisited = cellsVisited();
    return result;
  }

private:
  std::size_t blockIndex(std::int64_t bx, std::int64_t by, std::int64_t bz) const {
    return std::size_t((bz * blocks_[1] + by) * blocks_[0] + bx);
  }
  // Cells -1 .. B-2 are block 0, B-1 .. 2B-2 block 1, and so on.
  std::int64_t blockOf(std::int64_t cell) const { return (cell + 1) / block_; }
  std::int64_t rowY(std::size_t r) const { return std::int64_t(r % std::size_t(py_)) - 1; }
  std::int64_t rowZ(std::size_t r) const { return std::int64_t(r / std::size_t(py_)) - 1; }

  // Per row of blocks, which cells of a cell row lie in visited blocks (at x + 1; one more 0 at
  // each end, so cells -2 and dims read as unvisited); null when none does.
  void markCells() {
    const std::size_t blockRows = std::size_t(blocks_[1] * blocks_[2]), width = std::size_t(px_) + 2;
    cellMasks_.assign(blockRows * width, 0);
    blockRowVisited_.assign(blockRows, 0);
    for (std::size_t row = 0; row < blockRows; ++row) {
      std::uint8_t* mask = cellMasks_.data() + row * width + 1;
      for (std::int64_t bx = 0; bx < blocks_[0]; ++bx) {
        if (!visited_[row * std::size_t(blocks_[0]) + std::size_t(bx)]) continue;
        blockRowVisited_[row] = 1;
        const BlockCells cells = blockCells(bx, int(block_), d_[0]);
        for (std::int64_t x = cells.first; x <= cells.last; ++x) mask[x + 1] = 1;
      }
    }
  }
  const std::uint8_t* cellRow(std::int64_t y, std::int64_t z) const {
    if (y < -1 || y >= d_[1] || z < -1 || z >= d_[2]) return nullptr;
    const std::size_t row = std::size_t(blockOf(z) * blocks_[1] + blockOf(y));
    return blockRowVisited_[row] ? cellMasks_.data() + row * (std::size_t(px_) + 2) + 1 : nullptr;
  }

  // Inside is value > iso; points in the padding are outside. One byte per point, once, so the
  // passes read each row four times without comparing again; one more 0 ends each row.
  void markInside() {
    const std::size_t width = std::size_t(px_) + 1;
    inside_.assign(rows_ * width, 0);
    const float iso = iso_;  // a local: the byte stores could alias a member
    tbb::parallel_for(std::int64_t(0), d_[2], [&](std::int64_t z) {
      std::vector<float> scratch;
      for (std::int64_t y = 0; y < d_[1]; ++y) {
        const float* v = grid_.row(y, z, scratch);
        std::uint8_t* out = inside_.data() + std::size_t((z + 1) * py_ + y + 1) * width + 1;
        for (std::int64_t x = 0, n = d_[0]; x < n; ++x) out[x] = v[x] > iso;
      }
    });
  }
  const std::uint8_t* insideRow(std::int64_t y, std::int64_t z) const {
    if (y < 0 || y >= d_[1] || z < 0 || z >= d_[2]) return zeros_.data();
    return inside_.data() + std::size_t((z + 1) * py_ + y + 1) * (std::size_t(px_) + 1);
  }
  // Per point of cell row (y, z): its corners in rows (y, z), (y+1, z), (y, z+1), (y+1, z+1).
  void columns(std::int64_t y, std::int64_t z, std::vector<std::uint8_t>& out) const {
    const std::uint8_t *in0 = insideRow(y, z), *in1 = insideRow(y + 1, z), *in2 = insideRow(y, z + 1),
                       *in3 = insideRow(y + 1, z + 1);
    const std::size_t points = std::size_t(px_);
    out.resize(points);
    std::uint8_t* o = out.data();
    for (std::size_t i = 0; i < points; ++i) o[i] = std::uint8_t(in0[i] | in1[i] << 1 | in2[i] << 2 | in3[i] << 3);
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
    const float a = sample(x, y, z), b = sample(x + (axis == 0), y + (axis == 1), z + (axis == 2));
    const float t = std::clamp((iso_ - a) / (b - a), kOffCorner, 1 - kOffCorner);
    Vec3 p{double(x), double(y), double(z)};
    p[axis] += double(t);
    return p;
  }
  std::uint8_t* flagRow(std::size_t row) { return flags_.data() + row * std::size_t(px_); }
  const std::uint8_t* flagRow(std::size_t row) const { return flags_.data() + row * std::size_t(px_); }

  // Pass 1 for row r: its points' edge flags and counts, its cells' triangles and centres. An edge
  // that crosses gets a vertex when one of the four cells around it is visited (those cells exist:
  // a crossing edge has an end inside the grid).
  void countRow(std::size_t r, std::vector<std::uint8_t>& column, std::uint64_t& edges, std::uint64_t& triangles,
                std::uint64_t& centres) {
    const std::int64_t y = rowY(r), z = rowZ(r);
    // The cells around this row's edges: cell rows (y, z), (y-1, z), (y, z-1), (y-1, z-1).
    const std::uint8_t* cells[4] = {cellRow(y, z), cellRow(y - 1, z), cellRow(y, z - 1), cellRow(y - 1, z - 1)};
    if (!cells[0] && !cells[1] && !cells[2] && !cells[3]) return;
    const bool cellsHere = cells[0] != nullptr;
    for (const std::uint8_t*& c : cells) c = c ? c : zeros_.data() + 1;
    const std::uint8_t *c0 = cells[0], *c1 = cells[1], *c2 = cells[2], *c3 = cells[3];
    const std::uint8_t *c0Before = c0 - 1, *c1Before = c1 - 1, *c2Before = c2 - 1;  // cell x - 1 at i
    const std::uint8_t *in0 = insideRow(y, z), *in1 = insideRow(y + 1, z), *in2 = insideRow(y, z + 1);
    std::uint8_t* flags = flagRow(r);
    std::uint32_t count = 0;
    const std::size_t points = std::size_t(px_);  // a local: the byte stores could alias a member
    for (std::size_t i = 0; i < points; ++i) {     // point x = i - 1; cell x at i
      const std::uint8_t here = in0[i];
      const unsigned alongX = (here ^ in0[i + 1]) & (c0[i] | c1[i] | c2[i] | c3[i]);
      const unsigned alongY = (here ^ in1[i]) & (c0[i] | c0Before[i] | c2[i] | c2Before[i]);
      const unsigned alongZ = (here ^ in2[i]) & (c0[i] | c0Before[i] | c1[i] | c1Before[i]);
      flags[i] = std::uint8_t(alongX | alongY << 1 | alongZ << 2);
      count += alongX + alongY + alongZ;
    }
    edges = count;
    if (!cellsHere) return;
    columns(y, z, column);
    const std::uint8_t* side = column.data();
    for (std::size_t i = 0; i + 1 < points; ++i) {
      if (side[i] == side[i + 1] && (side[i] == 0 || side[i] == 15)) continue;  // all outside or all inside
      if (!c0[i]) continue;
      const int c = cellCase(side[i], side[i + 1]);
      triangles += caseTriangles_[c];
      centres += caseCentres_[c];
    }
  }

  // Pass 3: row r's vertices, in (x, axis) order, numbered first .. end - 1.
  void emitVertices(std::size_t r, std::uint64_t first, std::uint64_t end, Mesh& mesh) const {
    const std::uint8_t* flags = flagRow(r);
    const std::int64_t y = rowY(r), z = rowZ(r);
    for (std::int64_t x = -1; first < end; ++x) {
      const std::uint8_t bits = flags[x + 1];
      for (int axis = 0; bits && axis < 3; ++axis)
        if (bits >> axis & 1) mesh.positions[first++] = edgePoint(x, y, z, axis);
    }
  }

  // Pass 3: cell row r's triangles from `triangle`, its centre vertices from `centre`.
  void emitTriangles(std::size_t r, std::vector<std::uint8_t>& column, std::vector<std::uint8_t>& vertexAt,
                     const std::vector<std::uint64_t>& edgeStart, std::uint64_t triangle, std::uint64_t centre,
                     Mesh& mesh) const {
    const std::int64_t y = rowY(r), z = rowZ(r);
    const std::size_t rows[4] = {r, r + 1, r + std::size_t(py_), r + std::size_t(py_) + 1};
    const std::uint8_t* flags[4];
    std::uint32_t next[4];  // per point row: the index of the first vertex at the current x
    for (int i = 0; i < 4; ++i) {
      flags[i] = flagRow(rows[i]);
      next[i] = std::uint32_t(edgeStart[rows[i]]);  // run() checked that indices fit
    }
    const std::uint8_t* visited = cellRow(y, z);  // not null: this row has triangles
    columns(y, z, column);
    // A cell has surface only where one of its 12 edges has a vertex: at point x or x + 1 of one of
    // the four rows. Elsewhere the counters stay, so most of the row is one byte test per cell.
    const std::size_t points = std::size_t(px_);
    vertexAt.resize(points);
    std::uint8_t* at = vertexAt.data();
    for (std::size_t i = 0; i < points; ++i) at[i] = flags[0][i] | flags[1][i] | flags[2][i] | flags[3][i];
    const auto& table = caseTable();
    std::uint32_t* out = mesh.faceVertices.data() + std::size_t(triangle) * 3;
    for (std::int64_t x = -1; x < d_[0]; ++x) {
      const std::size_t i = std::size_t(x + 1);
      if (!at[i] && !at[i + 1]) continue;
      std::uint32_t here[4], after[4];  // first vertex index at points x and x + 1
      for (int k = 0; k < 4; ++k) {
        here[k] = next[k];
        after[k] = next[k] + edgeCount(flags[k][i]);
        next[k] = after[k];
      }
      if (!visited[i]) continue;
      const int c = cellCase(column[i], column[i + 1]);
      if (c == 0 || c == 255) continue;
      std::uint32_t ids[12];
      for (const Polygon& polygon : table.polygons[std::size_t(c)]) {
        for (std::int8_t e : polygon.edges) {
          const int a = kEdgeCorner[e][0], axis = kEdgeAxis[e];  // the edge runs from corner a along axis
          const int row = (a >> 1) & 3, dx = a & 1;
          ids[e] = (dx ? after[row] : here[row]) + edgeCount(flags[row][i + std::size_t(dx)] & ((1u << axis) - 1));
        }
        const auto& cycle = polygon.edges;
        const std::size_t n = cycle.size();
        if (polygon.apex >= 0) {
          // Fan in the cycle's order, which is the outward orientation.
          const std::size_t a = std::size_t(polygon.apex);
          for (std::size_t k = 1; k + 1 < n; ++k)
            for (std::size_t j : {a, (a + k) % n, (a + k + 1) % n}) *out++ = ids[cycle[j]];
        } else {
          // A centre vertex of this polygon alone, at the mean of its crossings.
          Vec3 mean{0, 0, 0};
          for (std::int8_t e : cycle) {
            const int a = kEdgeCorner[e][0];
            mean = mean + edgePoint(x + (a & 1), y + ((a >> 1) & 1), z + ((a >> 2) & 1), kEdgeAxis[e]);
          }
          mesh.positions[centre] = mean * (1.0 / double(n));
          for (std::size_t k = 0; k < n; ++k)
            for (std::uint32_t id : {std::uint32_t(centre), ids[cycle[k]], ids[cycle[(k + 1) % n]]}) *out++ = id;
          ++centre;
        }
      }
    }
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
  const std::size_t rows_;
  const std::vector<std::uint8_t> zeros_;  // a row of outside points, or of unvisited cells
  std::int64_t blocks_[3];
  std::vector<std::uint8_t> visited_;     // per block of cells
  std::vector<std::uint8_t> cellMasks_, blockRowVisited_;  // per row of blocks (markCells)
  std::vector<std::uint8_t> inside_;      // per point row (markInside)
  std::vector<std::uint8_t> flags_;       // per point: bit axis set when that edge has a vertex
  std::uint32_t caseTriangles_[256] = {}, caseCentres_[256] = {};
};

}  // namespace

MarchingResult marchingCubesCpu(const Grid& grid, float iso, int blockSize, const VisitBlock& visitBlock) {
  return RowMarcher(grid, iso, blockSize, visitBlock).run();
}

}  // namespace isoatlas::extract
