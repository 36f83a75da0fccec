#include "multires/dense_sampler.h"

#include <algorithm>
#include <limits>

#include "core/error.h"

namespace isoatlas::multires {
namespace {

// The barycentric coordinates of a point given in base triangle `from`, expressed in the frame of
// `to`, which shares an edge with it: `from`'s third corner is unfolded across the edge to
// (corner a + corner b - to's third corner), an affine map that both sides agree on.
bool unfold(const BaseMesh& base, std::uint32_t from, const std::array<double, 3>& bary, std::uint32_t to,
            std::array<double, 3>& out) {
  const auto& f = base.triangles[from];
  const auto& t = base.triangles[to];
  int shared = 0, apex = -1;
  double w[3] = {0, 0, 0};
  double apexWeight = 0;
  for (int i = 0; i < 3; ++i) {
    int at = -1;
    for (int j = 0; j < 3; ++j)
      if (t[j] == f[i]) at = j;
    if (at >= 0) w[at] += bary[i], ++shared;
    else apexWeight = bary[i];
  }
  if (shared != 2) return false;
  for (int j = 0; j < 3; ++j) {
    const bool inFrom = t[j] == f[0] || t[j] == f[1] || t[j] == f[2];
    if (!inFrom) apex = j;
  }
  for (int j = 0; j < 3; ++j) out[j] = w[j] + (j == apex ? -apexWeight : apexWeight);
  return true;
}

// A point of base triangle `from` whose weight lies only on corners `to` shares (a base vertex, or
// a point of a shared edge) is the same point of `to`: expressed there exactly.
bool express(const BaseMesh& base, std::uint32_t from, const std::array<double, 3>& bary, std::uint32_t to,
             std::array<double, 3>& out) {
  const auto& f = base.triangles[from];
  const auto& t = base.triangles[to];
  out = {0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    if (bary[i] == 0) continue;
    const auto* at = std::find(t.begin(), t.end(), f[i]);
    if (at == t.end()) return false;
    out[std::size_t(at - t.begin())] += bary[i];
  }
  return true;
}

}  // namespace

DenseSampler::DenseSampler(const Mesh& dense, const BaseMesh& base) : dense_(dense), base_(base), images_(base.triangleCount()) {
  require(base.denseTriangle.size() == dense.vertexCount(), "dense sampler: the parametrisation does not match the mesh");
  for (std::size_t f = 0; f < dense.faceCount(); ++f) {
    const auto c = dense.face(f);
    std::uint32_t tris[3];
    for (int i = 0; i < 3; ++i) tris[i] = base.denseTriangle[c[i]];
    for (int home = 0; home < 3; ++home) {
      const std::uint32_t t = tris[home];
      if (std::find(tris, tris + home, t) != tris + home) continue;  // one image per base triangle
      Image image{std::uint32_t(f), {}};
      bool ok = true;
      for (int i = 0; i < 3 && ok; ++i) {
        std::array<double, 3> b = base.denseBary[c[i]];
        if (tris[i] != t) ok = express(base, tris[i], base.denseBary[c[i]], t, b) || unfold(base, tris[i], base.denseBary[c[i]], t, b);
        image.uv[i] = {b[1], b[2]};
      }
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
