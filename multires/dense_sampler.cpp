#include "multires/dense_sampler.h"

#include <algorithm>
#include <limits>


#include "core/error.h"

namespace isoatlas::multires {

DenseSampler::DenseSampler(const Mesh& dense, const BaseMesh& base)
    : dense_(dense), base_(base), domain_(base), images_(base.triangleCount()) {
  require(base.denseTriangle.size() == dense.vertexCount(), "dense sampler: the parametrisation does not match the mesh");
  std::vector<std::vector<std::uint32_t>> star(base.vertexCount());  // base vertex -> its triangles
  for (std::uint32_t t = 0; t < base.triangleCount(); ++t)
    for (const std::uint32_t v : base.triangles[t]) star[v].push_back(t);
  std::vector<std::uint32_t> homes;
  for (std::size_t f = 0; f < dense.faceCount(); ++f) {
    const auto c = dense.face(f);
    homes.clear();
    for (int i = 0; i < 3; ++i)
      if (std::find(homes.begin(), homes.end(), base.denseTriangle[c[i]]) == homes.end()) homes.push_back(base.denseTriangle[c[i]]);
    // Corners in triangles around one base vertex that are not neighbours: the image crosses the
    // triangles between them too, so it goes into the vertex's whole star.
    if (homes.size() > 1) {
      std::vector<std::uint32_t> common;
      for (const std::uint32_t v : base.triangles[homes[0]])
        if (std::all_of(homes.begin(), homes.end(), [&](std::uint32_t t) {
              const auto& tri = base.triangles[t];
              return std::find(tri.begin(), tri.end(), v) != tri.end();
            }))
          common.push_back(v);
      if (common.size() == 1)
        for (const std::uint32_t t : star[common[0]])
          if (std::find(homes.begin(), homes.end(), t) == homes.end()) homes.push_back(t);
    }
    for (const std::uint32_t t : homes) {
      Image image{std::uint32_t(f), {}};
      const std::uint32_t from[3] = {base.denseTriangle[c[0]], base.denseTriangle[c[1]], base.denseTriangle[c[2]]};
      const BaseDomain::Bary bary[3] = {base.denseBary[c[0]], base.denseBary[c[1]], base.denseBary[c[2]]};
      BaseDomain::Bary b[3];
      const bool ok = domain_.transferAll(from, bary, 3, t, b);
      for (int i = 0; i < 3; ++i) image.uv[i] = {b[i][1], b[i][2]};
      if (ok) images_[t].push_back(image);
    }
  }
}

Vec3 DenseSampler::position(std::uint32_t triangle, const std::array<double, 3>& bary) const {
  const double px = bary[1], py = bary[2];
  const Image* best = nullptr;
  std::array<double, 3> bestWeights{};
  double bestMin = -std::numeric_limits<double>::infinity();
  for (const Image& image : images_[triangle]) {
    const auto& a = image.uv[0];
    const auto& b = image.uv[1];
    const auto& c = image.uv[2];
    const double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if (!(std::abs(area) > 1e-300)) continue;
    const double wa = ((b[0] - px) * (c[1] - py) - (b[1] - py) * (c[0] - px)) / area;
    const double wb = ((px - a[0]) * (c[1] - a[1]) - (py - a[1]) * (c[0] - a[0])) / area;
    const std::array<double, 3> w{wa, wb, 1 - wa - wb};
    const double lowest = std::min({w[0], w[1], w[2]});
    if (lowest > bestMin) bestMin = lowest, best = &image, bestWeights = w;
    if (lowest >= 0) break;
  }
  if (!best) return base_.pointAt(triangle, bary);
  // Outside every image (by rounding, or near a base vertex): clamp to the nearest one.
  double sum = 0;
  for (double& w : bestWeights) sum += (w = std::max(0.0, w));
  const auto c = dense_.face(best->denseFace);
  Vec3 p;
  for (int i = 0; i < 3; ++i) p = p + dense_.positions[c[i]] * (bestWeights[i] / sum);
  return p;
}

}  // namespace isoatlas::multires
