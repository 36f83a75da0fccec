#include "extract/marching_cubes.h"

#include "extract/gpu_marching_cubes.h"

#include <tbb/blocked_range.h>
#include <tbb/blocked_range3d.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <unordered_map>

namespace isoatlas::extract {
namespace {

// Corner k of a cell sits at (k & 1, (k >> 1) & 1, (k >> 2) & 1). Edge e joins kEdgeCorner[e][0] to
// kEdgeCorner[e][1] along axis kEdgeAxis[e], from the lower corner.
constexpr int kEdgeCorner[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                    {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
constexpr int kEdgeAxis[12] = {0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2};

// The six faces, each as four corners counter-clockwise seen from outside the cell.
constexpr int kFaceCorners[6][4] = {
    {0, 4, 6, 2},  // x = 0, outward -x
    {1, 3, 7, 5},  // x = 1, outward +x
    {0, 1, 5, 4},  // y = 0, outward -y
    {2, 6, 7, 3},  // y = 1, outward +y
    {0, 2, 3, 1},  // z = 0, outward -z
    {4, 5, 7, 6},  // z = 1, outward +z
};

int edgeBetween(int a, int b) {
  for (int e = 0; e < 12; ++e)
    if ((kEdgeCorner[e][0] == a && kEdgeCorner[e][1] == b) || (kEdgeCorner[e][0] == b && kEdgeCorner[e][1] == a)) return e;
  return -1;
}

// For each of the 256 inside/outside patterns: the polygons, as cycles of cell edges, built from
// the per-face segments (entering crossing -> leaving crossing, walking each face counter-clockwise
// from outside; an ambiguous face cuts each inside corner off on its own).
bool onFace(int edge, int face) {
  int hits = 0;
  for (int k : kFaceCorners[face]) hits += (k == kEdgeCorner[edge][0]) + (k == kEdgeCorner[edge][1]);
  return hits == 2;
}
bool shareFace(int a, int b) {
  for (int f = 0; f < 6; ++f)
    if (onFace(a, f) && onFace(b, f)) return true;
  return false;
}

struct Polygon {
  std::vector<std::int8_t> edges;  // the cycle of cell edges, outward orientation
  int apex;                        // fan from this corner, or -1: fan from a centre vertex of its own
};

// A fan diagonal joining two crossings on one face could be drawn by the cell across that face too
// (an ambiguous face whose two segments both lie in one polygon on each side), giving an edge of four
// triangles. So the apex is chosen to draw no such diagonal; when none can, a centre vertex is used.
int chooseApex(const std::vector<std::int8_t>& cycle) {
  const int n = int(cycle.size());
  for (int a = 0; a < n; ++a) {
    bool ok = true;
    for (int i = 0; i < n && ok; ++i) {
      const bool adjacent = i == a || i == (a + 1) % n || (i + 1) % n == a;
      if (!adjacent && shareFace(cycle[std::size_t(a)], cycle[std::size_t(i)])) ok = false;
    }
    if (ok) return a;
  }
  return -1;
}

struct CaseTable {
  std::array<std::vector<Polygon>, 256> polygons;
  CaseTable() {
    for (int c = 0; c < 256; ++c) {
      int next[12];
      std::fill(std::begin(next), std::end(next), -1);
      auto inside = [c](int corner) { return (c >> corner) & 1; };
      for (const auto& face : kFaceCorners) {
        for (int i = 0; i < 4; ++i) {
          const int corner = face[i];
          if (!inside(corner)) continue;
          const int before = face[(i + 3) % 4];
          if (inside(before)) continue;  // this inside run starts earlier on the face
          // Walk the inside run forward to its last corner; the run leaves on the following edge.
          int j = i;
          while (inside(face[(j + 1) % 4]) && (j + 1) % 4 != i) j = (j + 1) % 4;
          const int entering = edgeBetween(before, corner);
          const int leaving = edgeBetween(face[j], face[(j + 1) % 4]);
          next[entering] = leaving;
        }
      }
      bool used[12] = {};
      for (int e = 0; e < 12; ++e) {
        if (next[e] < 0 || used[e]) continue;
        std::vector<std::int8_t> cycle;
        for (int k = e; !used[k]; k = next[k]) {
          used[k] = true;
          cycle.push_back(std::int8_t(k));
        }
        const int apex = chooseApex(cycle);
        polygons[std::size_t(c)].push_back({cycle, apex});
      }
    }
  }
};

const CaseTable& caseTable() {
  static const CaseTable table;
  return table;
}

}  // namespace

const PackedCaseTable& packedCaseTable() {
  static const PackedCaseTable packed = [] {
    PackedCaseTable p;
    for (const auto& polygons : caseTable().polygons) {
      p.index.push_back(std::int32_t(p.polygons.size()));
      p.index.push_back(std::int32_t(polygons.size()));
      for (const Polygon& polygon : polygons) {
        p.polygons.push_back(polygon.apex);
        p.polygons.push_back(std::int32_t(polygon.edges.size()));
        for (std::int8_t e : polygon.edges) p.polygons.push_back(e);
      }
    }
    return p;
  }();
  return packed;
}

namespace {

constexpr float kOffCorner = 1e-3f;  // crossing points stay this far (in voxels) from grid points

struct Corner {
  std::int64_t key;  // (lower grid point + 1, axis): shared by every cell around the grid edge
  Vec3 position;
};

// What one block of cells produces; blocks are merged in block order, so the mesh does not depend
// on how threads split the work.
struct BlockOutput {
  std::vector<std::int64_t> triangleKeys;
  std::vector<Corner> corners;
  std::int64_t cells = 0;
};

}  // namespace

MarchingResult marchingCubes(const Grid& grid, float iso, int blockSize,
                             const std::function<bool(std::int64_t, std::int64_t, std::int64_t)>& visitBlock) {
  const CaseTable& table = caseTable();
  const auto dims = grid.dims;
  // Samples outside the grid mirror the nearest grid value about iso when it is inside, so the
  // padded field is outside there and a border surface sits half a voxel past the last voxel.
  auto sample = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    const std::int64_t cx = std::clamp<std::int64_t>(x, 0, dims[0] - 1), cy = std::clamp<std::int64_t>(y, 0, dims[1] - 1),
                       cz = std::clamp<std::int64_t>(z, 0, dims[2] - 1);
    const float v = grid.at(cx, cy, cz);
    if (cx == x && cy == y && cz == z) return v;
    return v > iso ? 2 * iso - v : v;
  };
  // Cells -1 .. dims-1 on each axis; the key space covers grid points -1 .. dims.
  const std::int64_t px = dims[0] + 2, py = dims[1] + 2;
  auto keyOf = [&](std::int64_t x, std::int64_t y, std::int64_t z, int axis) {
    return (((z + 1) * py + (y + 1)) * px + (x + 1)) * 3 + axis;
  };
  const std::int64_t cells[3] = {dims[0] + 1, dims[1] + 1, dims[2] + 1};
  const std::int64_t blocks[3] = {(cells[0] + blockSize - 1) / blockSize, (cells[1] + blockSize - 1) / blockSize,
                                  (cells[2] + blockSize - 1) / blockSize};

  std::vector<BlockOutput> outputs(std::size_t(blocks[0] * blocks[1] * blocks[2]));
  tbb::enumerable_thread_specific<std::unordered_map<std::int64_t, std::uint32_t>> seenPerThread;
  tbb::parallel_for(tbb::blocked_range3d<std::int64_t>(0, blocks[2], 0, blocks[1], 0, blocks[0]), [&](const auto& r) {
    auto& seen = seenPerThread.local();
    for (std::int64_t bz = r.pages().begin(); bz != r.pages().end(); ++bz)
      for (std::int64_t by = r.rows().begin(); by != r.rows().end(); ++by)
        for (std::int64_t bx = r.cols().begin(); bx != r.cols().end(); ++bx) {
          if (visitBlock && !visitBlock(bx, by, bz)) continue;
          BlockOutput& local = outputs[std::size_t((bz * blocks[1] + by) * blocks[0] + bx)];
          seen.clear();
          const std::int64_t x0 = bx * blockSize - 1, y0 = by * blockSize - 1, z0 = bz * blockSize - 1;
          const std::int64_t x1 = std::min(x0 + blockSize, dims[0]), y1 = std::min(y0 + blockSize, dims[1]),
                             z1 = std::min(z0 + blockSize, dims[2]);
          for (std::int64_t z = z0; z < z1; ++z)
            for (std::int64_t y = y0; y < y1; ++y)
              for (std::int64_t x = x0; x < x1; ++x) {
                ++local.cells;
                float v[8];
                int pattern = 0;
                for (int k = 0; k < 8; ++k) {
                  v[k] = sample(x + (k & 1), y + ((k >> 1) & 1), z + ((k >> 2) & 1));
                  pattern |= (v[k] > iso ? 1 : 0) << k;
                }
                if (pattern == 0 || pattern == 255) continue;
                std::uint32_t ids[12];
                int polygonIndex = 0;
                for (const Polygon& polygon : table.polygons[std::size_t(pattern)]) {
                  for (std::int8_t e : polygon.edges) {
                    const int a = kEdgeCorner[e][0], b = kEdgeCorner[e][1];
                    const std::int64_t ax = x + (a & 1), ay = y + ((a >> 1) & 1), az = z + ((a >> 2) & 1);
                    const std::int64_t key = keyOf(ax, ay, az, kEdgeAxis[e]);
                    auto [it, fresh] = seen.try_emplace(key, std::uint32_t(local.corners.size()));
                    if (fresh) {
                      const float t = std::clamp((iso - v[a]) / (v[b] - v[a]), kOffCorner, 1 - kOffCorner);
                      Vec3 p{double(ax), double(ay), double(az)};
                      p[kEdgeAxis[e]] += double(t);
                      local.corners.push_back({key, p});
                    }
                    ids[e] = it->second;
                  }
                  // Fan in the cycle's order, which is the outward orientation.
                  const auto& cycle = polygon.edges;
                  const std::size_t n = cycle.size();
                  if (polygon.apex >= 0) {
                    const std::size_t a = std::size_t(polygon.apex);
                    for (std::size_t i = 1; i + 1 < n; ++i)
                      for (std::size_t k : {a, (a + i) % n, (a + i + 1) % n})
                        local.triangleKeys.push_back(local.corners[ids[cycle[k]]].key);
                  } else {
                    // A centre vertex of this polygon alone: its key lies past every edge key, in cell
                    // order (the GPU path numbers them the same way).
                    const std::int64_t cellIndex = ((z + 1) * (dims[1] + 1) + (y + 1)) * (dims[0] + 1) + (x + 1);
                    const std::int64_t centreKey = px * py * (dims[2] + 2) * 3 + cellIndex * 8 + polygonIndex;
                    Vec3 centre{0, 0, 0};
                    for (std::int8_t e : cycle) centre = centre + local.corners[ids[e]].position;
                    local.corners.push_back({centreKey, centre * (1.0 / double(n))});
                    for (std::size_t i = 0; i < n; ++i)
                      for (std::int64_t key : {centreKey, local.corners[ids[cycle[i]]].key, local.corners[ids[cycle[(i + 1) % n]]].key})
                        local.triangleKeys.push_back(key);
                  }
                  ++polygonIndex;
                }
              }
        }
  });

  // Merge: one vertex per grid edge, found by key.
  MarchingResult result;
  std::vector<Corner> all;
  std::size_t triangleCorners = 0;
  for (const BlockOutput& l : outputs) {
    all.insert(all.end(), l.corners.begin(), l.corners.end());
    triangleCorners += l.triangleKeys.size();
    result.cellsVisited += l.cells;
  }
  std::sort(all.begin(), all.end(), [](const Corner& a, const Corner& b) { return a.key < b.key; });
  all.erase(std::unique(all.begin(), all.end(), [](const Corner& a, const Corner& b) { return a.key == b.key; }), all.end());
  Mesh& mesh = result.mesh;
  mesh.positions.reserve(all.size());
  for (const Corner& c : all) mesh.positions.push_back(c.position);
  auto globalId = [&](std::int64_t key) {
    return std::uint32_t(std::lower_bound(all.begin(), all.end(), key, [](const Corner& c, std::int64_t k) { return c.key < k; }) -
                         all.begin());
  };
  mesh.faceVertices.resize(triangleCorners);
  mesh.faceOffsets.resize(triangleCorners / 3 + 1);
  for (std::size_t t = 0; t < mesh.faceOffsets.size(); ++t) mesh.faceOffsets[t] = std::uint32_t(3 * t);
  // Each block's corners are looked up once; its triangles then map through that table.
  std::vector<std::size_t> start(outputs.size() + 1, 0);
  for (std::size_t b = 0; b < outputs.size(); ++b) start[b + 1] = start[b] + outputs[b].triangleKeys.size();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, outputs.size()), [&](const auto& range) {
    std::unordered_map<std::int64_t, std::uint32_t> ids;
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      const BlockOutput& l = outputs[b];
      ids.clear();
      for (const Corner& c : l.corners) ids.emplace(c.key, globalId(c.key));
      for (std::size_t i = 0; i < l.triangleKeys.size(); ++i) mesh.faceVertices[start[b] + i] = ids.at(l.triangleKeys[i]);
    }
  });
  return result;
}

}  // namespace isoatlas::extract
