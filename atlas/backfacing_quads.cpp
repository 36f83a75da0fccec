#include "atlas/backfacing_quads.h"

#include <oneapi/tbb/parallel_for.h>

#include <array>
#include <vector>

#include "atlas/reconstruct.h"
#include "core/error.h"

namespace isoatlas::atlas {
namespace {

// The texels (column, row) of triangle t of quad (a, b), as squareTriangles cuts it.
std::array<std::array<std::uint32_t, 2>, 3> triangleTexels(std::uint32_t a, std::uint32_t b, int t) {
  const std::array<std::array<std::uint32_t, 2>, 4> corner{{{a, b}, {a + 1, b}, {a + 1, b + 1}, {a, b + 1}}};
  const auto k = squareTriangles(a, b)[std::size_t(t)];
  return {corner[std::size_t(k[0])], corner[std::size_t(k[1])], corner[std::size_t(k[2])]};
}

template <class TriangleTurns>
BackFacingQuads countTurningQuads(const Atlas& atlas, const TriangleTurns& quadTurns) {
  const std::uint32_t n = atlas.layout.chartSize, charts = atlas.layout.charts;
  BackFacingQuads out;
  std::vector<std::uint64_t>& perChart = out.perChart;
  perChart.assign(charts, 0);
  tbb::parallel_for(std::uint32_t(0), charts, [&](std::uint32_t c) {
    std::uint64_t turned = 0;
    for (std::uint32_t b = 0; b + 1 < n; ++b)
      for (std::uint32_t a = 0; a + 1 < n; ++a) turned += quadTurns(atlas, c, a, b);
    perChart[c] = turned;
  });
  out.total = std::uint64_t(charts) * (n - 1) * (n - 1);
  for (std::uint32_t c = 0; c < charts; ++c) {
    out.quads += perChart[c];
    out.charts += perChart[c] > 0;
    if (perChart[c] > out.worstChartQuads) out.worstChartQuads = perChart[c], out.worstChart = c;
  }
  if (charts > 0) out.worstChartCentre = atlas.position(out.worstChart, n / 2, n / 2);
  return out;
}

void requireTriangleFaceNormals(const Atlas& atlas) {
  require(atlas.triangleFaceNormals.size() == 2 * atlas.normals.size(),
          "folded texel quads: the atlas has no dense face normals (measure it where it is made, with its dense mesh)");
}

}  // namespace

bool quadFacesBackwards(const Atlas& atlas, std::uint32_t c, std::uint32_t a, std::uint32_t b) {
  for (int t = 0; t < 2; ++t) {
    Vec3 p[3], n[3];
    for (int k = 0; const auto& [i, j] : triangleTexels(a, b, t)) p[k] = atlas.position(c, i, j), n[k++] = atlas.normal(c, i, j);
    if (facesBackwards(p[0], p[1], p[2], n[0], n[1], n[2])) return true;
  }
  return false;
}

bool quadFolds(const Atlas& atlas, std::uint32_t c, std::uint32_t a, std::uint32_t b) {
  requireTriangleFaceNormals(atlas);
  for (int t = 0; t < 2; ++t) {
    Vec3 p[3];
    for (int k = 0; const auto& [i, j] : triangleTexels(a, b, t)) p[k++] = atlas.position(c, i, j);
    if (dot(cross(p[1] - p[0], p[2] - p[0]), atlas.triangleFaceNormal(c, a, b, t)) < 0) return true;
  }
  return false;
}

BackFacingQuads countBackFacingQuads(const Atlas& atlas) { return countTurningQuads(atlas, quadFacesBackwards); }
BackFacingQuads countFoldedQuads(const Atlas& atlas) {
  requireTriangleFaceNormals(atlas);  // here too: an atlas without charts asks quadFolds nothing
  return countTurningQuads(atlas, quadFolds);
}

}  // namespace isoatlas::atlas
