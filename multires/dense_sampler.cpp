#include "multires/dense_sampler.h"

#include <algorithm>
#include <limits>

#include "core/error.h"
#include "multires/base_domain.h"

namespace isoatlas::multires {

DenseSampler::DenseSampler(const Mesh& dense, const BaseMesh& base)
    : dense_(dense), images_(base.triangleCount()) {
  require(base.denseTriangle.size() == dense.vertexCount(), "dense sampler: the parametrisation does not match the mesh");
  require(dense.allFacesHave(3), "dense sampler: the dense mesh must be made of triangles");
  for (const auto& t : base.triangles) baseCorners_.push_back({base.positions[t[0]], base.positions[t[1]], base.positions[t[2]]});
  const BaseDomain domain(base);
  // Each dense triangle through the one chart that holds its corners (as untangling sees it),
  // imaged in its corners' base triangles; when that chart is a base vertex's star the image may
  // cross the triangles between them, so it goes into the whole star.
  BaseDomain::Chart chart;
  std::vector<std::uint32_t> homes;
  for (std::size_t f = 0; f < dense.faceCount(); ++f) {
    const auto c = dense.face(f);
    std::array<BaseDomain::Point2, 3> p;
    if (!domain.chartDenseTriangle(c, chart, p)) continue;  // corners too far apart to image
    homes = {base.denseTriangle[c[0]], base.denseTriangle[c[1]], base.denseTriangle[c[2]]};
    if (chart.vertex != BaseDomain::kNone) homes.insert(homes.end(), chart.star.begin(), chart.star.end());
    std::sort(homes.begin(), homes.end());
    homes.erase(std::unique(homes.begin(), homes.end()), homes.end());
    for (const std::uint32_t t : homes) {
      Image image{std::uint32_t(f), {}};
      bool ok = true;
      for (int i = 0; i < 3 && ok; ++i) {
        BaseDomain::Bary b;
        ok = domain.inFrame(chart, p[i], t, b);
        image.uv[i] = {b[1], b[2]};
      }
      if (ok) images_[t].push_back(image);
    }
  }
}

Vec3 DenseSampler::position(std::uint32_t triangle, const std::array<double, 3>& bary) const {
  const std::vector<Image>& images = images_[triangle];
  const TriangleHit hit =
      locateInTriangles({bary[1], bary[2]}, images.size(), [&](std::size_t i) { return images[i].uv; });
  if (hit.triangle == kNoTriangleHit) {
    const auto& c = baseCorners_[triangle];
    return c[0] * bary[0] + c[1] * bary[1] + c[2] * bary[2];
  }
  // Outside every image (by rounding, or near a base vertex): the nearest one, clamped onto it.
  const auto c = dense_.face(images[hit.triangle].denseFace);
  Vec3 p;
  for (int i = 0; i < 3; ++i) p = p + dense_.positions[c[i]] * hit.bary[i];
  return p;
}

}  // namespace isoatlas::multires
