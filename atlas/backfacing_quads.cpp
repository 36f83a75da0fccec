#include "atlas/backfacing_quads.h"

#include <oneapi/tbb/parallel_for.h>

#include <array>
#include <vector>

#include "atlas/reconstruct.h"

namespace isoatlas::atlas {

bool quadFacesBackwards(const Atlas& atlas, std::uint32_t c, std::uint32_t a, std::uint32_t b) {
  const std::array<std::array<std::uint32_t, 2>, 4> corner{{{a, b}, {a + 1, b}, {a + 1, b + 1}, {a, b + 1}}};
  for (const auto& t : squareTriangles(a, b)) {
    Vec3 p[3], n[3];
    for (int k = 0; k < 3; ++k) {
      const auto [i, j] = corner[std::size_t(t[std::size_t(k)])];
      p[k] = atlas.position(c, i, j), n[k] = atlas.normal(c, i, j);
    }
    if (facesBackwards(p[0], p[1], p[2], n[0], n[1], n[2])) return true;
  }
  return false;
}

BackFacingQuads countBackFacingQuads(const Atlas& atlas) {
  const std::uint32_t n = atlas.layout.chartSize, charts = atlas.layout.charts;
  BackFacingQuads out;
  std::vector<std::uint64_t>& perChart = out.perChart;
  perChart.assign(charts, 0);
  tbb::parallel_for(std::uint32_t(0), charts, [&](std::uint32_t c) {
    std::uint64_t turned = 0;
    for (std::uint32_t b = 0; b + 1 < n; ++b)
      for (std::uint32_t a = 0; a + 1 < n; ++a) turned += quadFacesBackwards(atlas, c, a, b);
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

}  // namespace isoatlas::atlas
