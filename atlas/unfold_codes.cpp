#include "atlas/unfold_codes.h"

#include <tbb/parallel_for.h>

#include <array>
#include <atomic>

#include "atlas/code_shell.h"
#include "atlas/reconstruct.h"

namespace isoatlas::atlas {
namespace {

using Code = std::array<std::uint16_t, 3>;
constexpr int kFolded = 16;  // above the eight triangles round a texel, collapsed

Vec3 vec(const std::array<float, 3>& p) { return {p[0], p[1], p[2]}; }

// One chart's decoded positions, and whether its triangles fold there.
struct ChartFolds {
  const Atlas& atlas;
  const Atlas& decoded;
  std::uint32_t c, n;
  bool faceNormals;

  // Whether triangle t of square (a, b) folds with texel (i, j) at `at` (the others where decoded):
  // 16 when it faces against the surface, 1 when it has no area (a nudge must not trade a fold for a
  // collapse, nor a collapse for a fold), 0 otherwise.
  int folds(std::uint32_t a, std::uint32_t b, int t, std::uint32_t i, std::uint32_t j, const Vec3& at) const {
    static constexpr std::array<std::array<std::uint32_t, 2>, 4> kCorner{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
    Vec3 p[3], q[3];
    for (int k = 0; k < 3; ++k) {
      const auto& o = kCorner[std::size_t(squareTriangles(a, b)[std::size_t(t)][std::size_t(k)])];
      const std::uint32_t x = a + o[0], y = b + o[1];
      p[k] = x == i && y == j ? at : decoded.position(c, x, y);
      q[k] = atlas.position(c, x, y);
    }
    const Vec3 facing = faceNormals ? atlas.triangleFaceNormal(c, a, b, t) : cross(q[1] - q[0], q[2] - q[0]);
    const double turn = dot(cross(p[1] - p[0], p[2] - p[0]), facing);
    return turn < 0 ? kFolded : turn == 0 && dot(facing, facing) > 0 ? 1 : 0;
  }
  // The triangles of the (up to) four squares round texel (i, j) that fold with it at `at`, scored as
  // `folds` scores them (fewer folds first, then fewer collapses).
  int foldsRound(std::uint32_t i, std::uint32_t j, const Vec3& at) const {
    int count = 0;
    for (std::uint32_t b = j > 0 ? j - 1 : 0; b <= j && b + 1 < n; ++b)
      for (std::uint32_t a = i > 0 ? i - 1 : 0; a <= i && a + 1 < n; ++a)
        for (int t = 0; t < 2; ++t) count += folds(a, b, t, i, j, at);
    return count;
  }
};

// Texel (i, j)'s code `code` to the code within kReach steps of its rounded code `rounded` along every
// axis with the fewest folds round it, fewer than `code` has (the nearest to the atlas's position
// `want` among those), trying the nearer shells first. Returns whether it moved.
constexpr int kReach = 2;
bool nudge(const ChartFolds& chart, const QuantisedChart& q, const Code& rounded, const Vec3& want, std::uint32_t i,
           std::uint32_t j, Code& code) {
  int fewest = chart.foldsRound(i, j, vec(decodePosition(q, code)));
  if (fewest == 0) return false;
  Code best = code;
  double nearest = -1;
  for (int reach = 0; reach <= kReach && fewest > 0; ++reach)  // 0: back to the rounded code
    forEachCodeInShell(q, rounded, reach, [&](const Code& next) {
      const Vec3 p = vec(decodePosition(q, next));
      const int folds = chart.foldsRound(i, j, p);
      const double e = dot(p - want, p - want);
      if (folds < fewest || (folds == fewest && nearest >= 0 && e < nearest)) fewest = folds, best = next, nearest = e;
    });
  if (nearest < 0) return false;
  code = best;
  return true;
}

}  // namespace

std::uint64_t unfoldRoundedTexels(const Atlas& atlas, std::vector<QuantisedChart>& charts, Atlas& decoded) {
  const AtlasLayout& layout = atlas.layout;
  const std::uint32_t n = layout.chartSize;
  const bool faceNormals = atlas.triangleFaceNormals.size() == 2 * atlas.normals.size();
  std::atomic<std::uint64_t> moved = 0;
  tbb::parallel_for(std::uint32_t(0), layout.charts, [&](std::uint32_t c) {  // moves stay inside their chart
    const ChartFolds chart{atlas, decoded, c, n, faceNormals};
    QuantisedChart& q = charts[c];
    const std::vector<Code> rounded = q.positions;
    for (int sweep = 0; sweep < 3; ++sweep) {  // a move can unfold, or fold, its neighbours' triangles
      bool any = false;
      for (std::uint32_t j = 1; j + 1 < n; ++j)
        for (std::uint32_t i = 1; i + 1 < n; ++i) {
          const std::size_t k = std::size_t(j) * n + i, at = layout.texel(c, i, j);
          if (!nudge(chart, q, rounded[k], vec(atlas.positions[at]), i, j, q.positions[k])) continue;
          decoded.positions[at] = decodePosition(q, q.positions[k]);
          any = true;
        }
      if (!any) break;
    }
    std::uint64_t movedHere = 0;
    for (std::size_t k = 0; k < rounded.size(); ++k) movedHere += q.positions[k] != rounded[k];
    moved += movedHere;
  });
  return moved;
}

}  // namespace isoatlas::atlas
