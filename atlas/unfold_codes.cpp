#include "atlas/unfold_codes.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>

#include "atlas/reconstruct.h"

namespace isoatlas::atlas {
namespace {

using Code = std::array<std::uint16_t, 3>;

Vec3 vec(const std::array<float, 3>& p) { return {p[0], p[1], p[2]}; }

// One chart's decoded positions, and whether its triangles fold there.
struct ChartFolds {
  const Atlas& atlas;
  const Atlas& decoded;
  std::uint32_t c, n;
  bool faceNormals;

  // Whether triangle t of square (a, b) folds with texel (i, j) at `at` (the others where decoded).
  bool folds(std::uint32_t a, std::uint32_t b, int t, std::uint32_t i, std::uint32_t j, const Vec3& at) const {
    static constexpr std::array<std::array<std::uint32_t, 2>, 4> kCorner{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
    Vec3 p[3], q[3];
    for (int k = 0; k < 3; ++k) {
      const auto& o = kCorner[std::size_t(squareTriangles(a, b)[std::size_t(t)][std::size_t(k)])];
      const std::uint32_t x = a + o[0], y = b + o[1];
      p[k] = x == i && y == j ? at : decoded.position(c, x, y);
      q[k] = atlas.position(c, x, y);
    }
    const Vec3 facing = faceNormals ? atlas.triangleFaceNormal(c, a, b, t) : cross(q[1] - q[0], q[2] - q[0]);
    return dot(cross(p[1] - p[0], p[2] - p[0]), facing) < 0;
  }
  // How many triangles of the (up to) four squares round texel (i, j) fold with it at `at`.
  int foldsRound(std::uint32_t i, std::uint32_t j, const Vec3& at) const {
    int count = 0;
    for (std::uint32_t b = j > 0 ? j - 1 : 0; b <= j && b + 1 < n; ++b)
      for (std::uint32_t a = i > 0 ? i - 1 : 0; a <= i && a + 1 < n; ++a)
        for (int t = 0; t < 2; ++t) count += folds(a, b, t, i, j, at);
    return count;
  }
};

}  // namespace

std::uint64_t unfoldRoundedTexels(const Atlas& atlas, const multires::BaseMesh& base, std::vector<QuantisedChart>& charts) {
  const AtlasLayout& layout = atlas.layout;
  const std::uint32_t n = layout.chartSize;
  Atlas decoded;
  decoded.layout = layout;
  dequantiseAtlas(charts, base, decoded);
  const bool faceNormals = atlas.triangleFaceNormals.size() == 2 * atlas.normals.size();
  std::atomic<std::uint64_t> moved = 0;
  tbb::parallel_for(std::uint32_t(0), layout.charts, [&](std::uint32_t c) {  // moves stay inside their chart
    const ChartFolds chart{atlas, decoded, c, n, faceNormals};
    QuantisedChart& q = charts[c];
    std::uint64_t movedHere = 0;
    for (int sweep = 0; sweep < 3; ++sweep) {
      std::uint64_t movedNow = 0;
      for (std::uint32_t j = 1; j + 1 < n; ++j)
        for (std::uint32_t i = 1; i + 1 < n; ++i) {
          const std::size_t at = layout.texel(c, i, j);
          int fewest = chart.foldsRound(i, j, decoded.position(c, i, j));
          if (fewest == 0) continue;
          Code& code = q.positions[std::size_t(j) * n + i];
          const Vec3 want = vec(atlas.positions[at]);
          for (int reach = 1; reach <= 2 && fewest > 0; ++reach) {
            Code best = code;
            double nearest = -1;
            for (int dz = -reach; dz <= reach; ++dz)
              for (int dy = -reach; dy <= reach; ++dy)
                for (int dx = -reach; dx <= reach; ++dx) {
                  if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != reach) continue;  // this shell only
                  const int d[3] = {dx, dy, dz};
                  Code next = code;
                  bool valid = true;
                  for (int a = 0; a < 3; ++a) {
                    const int v = int(code[a]) + d[a];
                    valid &= (d[a] == 0 || q.step[a] > 0) && v >= 0 && v <= int(kLargestPositionCode);
                    next[a] = std::uint16_t(std::clamp(v, 0, int(kLargestPositionCode)));
                  }
                  if (!valid) continue;
                  const Vec3 p = vec(decodePosition(q, next));
                  const int folds = chart.foldsRound(i, j, p);
                  const double e = dot(p - want, p - want);
                  if (folds < fewest || (folds == fewest && nearest >= 0 && e < nearest)) fewest = folds, best = next, nearest = e;
                }
            if (nearest >= 0) {
              code = best;
              decoded.positions[at] = decodePosition(q, code);
              ++movedNow;
            }
          }
        }
      movedHere += movedNow;
      if (movedNow == 0) break;
    }
    moved += movedHere;
  });
  return moved;
}

}  // namespace isoatlas::atlas
