#include "multires/dense_sampler.h"

#include <algorithm>
#include <limits>

#include "core/error.h"

namespace isoatlas::multires {

DenseSampler::DenseSampler(const Mesh& dense, const BaseMesh& base)
    : dense_(dense), base_(base), domain_(base), images_(base.triangleCount()) {
  require(base.denseTriangle.size() == dense.vertexCount(), "dense sampler: the parametrisation does not match the mesh");
  // Each dense triangle through the one chart that holds its corners (as untangling sees it),
  // imaged in its corners' base triangles; when that chart is a base vertex's star the image may
  // cross the triangles between them, so it goes into the whole star.
  BaseDomain::Chart chart;
  std::vector<std::uint32_t> homes;
  for (std::size_t f = 0; f < dense.faceCount(); ++f) {
    const auto c = dense.face(f);
    const std::uint32_t from[3] = {base.denseTriangle[c[0]], base.denseTriangle[c[1]], base.denseTriangle[c[2]]};
    const BaseDomain::Bary bary[3] = {base.denseBary[c[0]], base.denseBary[c[1]], base.denseBary[c[2]]};
    BaseDomain::Point2 p[3];
    if (!domain_.chartFor(from, bary, 3, from[0], chart)) continue;  // corners too far apart to image
    bool charted = true;
    for (int i = 0; i < 3; ++i) charted = charted && domain_.toChart(chart, from[i], bary[i], p[i]);
    if (!charted) continue;
    homes.assign(from, from + 3);
    if (chart.vertex != BaseDomain::kNone) homes.insert(homes.end(), chart.star.begin(), chart.star.end());
    std::sort(homes.begin(), homes.end());
    homes.erase(std::unique(homes.begin(), homes.end()), homes.end());
    for (const std::uint32_t t : homes) {
      Image image{std::uint32_t(f), {}};
      bool ok = true;
      for (int i = 0; i < 3 && ok; ++i) {
        BaseDomain::Bary b;
        ok = domain_.inFrame(chart, p[i], t, b);
        image.uv[i] = {b[1], b[2]};
      }
      if (ok) images_[t].push_back(image);
    }
  }
}

Vec3 DenseSampler::position(std::uint32_t triangle, const std::array<double, 3>& bary) const {
  const Vec2 point{bary[1], bary[2]};
  const Image* best = nullptr;
  std::array<double, 3> bestWeights{};
  double bestMin = -std::numeric_limits<double>::infinity();
  for (const Image& image : images_[triangle]) {
    if (orient2(image.uv[0], image.uv[1], image.uv[2]) == 0) continue;
    const std::array<double, 3> w = barycentric2(point, image.uv[0], image.uv[1], image.uv[2]);
    const double lowest = std::min({w[0], w[1], w[2]});
    if (lowest > bestMin) bestMin = lowest, best = &image, bestWeights = w;
    if (lowest >= 0) break;
  }
  if (!best) return base_.pointAt(triangle, bary);
  // Outside every image (by rounding, or near a base vertex): clamp to the nearest one.
  clampToTriangle(bestWeights);
  const auto c = dense_.face(best->denseFace);
  Vec3 p;
  for (int i = 0; i < 3; ++i) p = p + dense_.positions[c[i]] * bestWeights[i];
  return p;
}

}  // namespace isoatlas::multires
