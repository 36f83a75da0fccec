#include "multires/weld_distance.h"

#include <algorithm>
#include <limits>

namespace isoatlas::multires {

double weldDistance2(const FanPoint& apex, std::span<const FanPoint> rim, std::span<const FanPoint> dense,
                     double bound) {
  const std::size_t faces = rim.size() < 2 ? 0 : rim.size() - 1;
  if (faces == 0) return 0;
  double worst = 0;
  // Dense vertices to their images: the face holding each best (largest smallest weight; outside
  // all only by rounding), searched from the face that held the last one (the list runs face by
  // face, so most searches end at the first try).
  std::size_t faceHint = 0;
  for (const FanPoint& p : dense) {
    std::array<double, 3> best{};
    double bestLowest = -std::numeric_limits<double>::infinity();
    for (std::size_t m = 0; m < faces; ++m) {
      const std::size_t f = (faceHint + m) % faces;
      const auto b = barycentric2(p.plane, apex.plane, rim[f].plane, rim[f + 1].plane);
      const double lowest = std::min({b[0], b[1], b[2]});
      if (lowest > bestLowest) bestLowest = lowest, best = b, faceHint = f;
      if (lowest >= 0) break;
    }
    clampToTriangle(best);
    const Vec3 image = apex.position * best[0] + rim[faceHint].position * best[1] + rim[faceHint + 1].position * best[2];
    worst = std::max(worst, dot(image - p.position, image - p.position));
    if (worst >= bound) return worst;
  }
  // The fan to the dense vertices, at the new faces' centroids and the new spokes' midpoints; a
  // search stops at a vertex nearer than the worst so far, which cannot raise it.
  std::size_t pointHint = 0;
  auto measure = [&](const Vec3& sample) {
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t m = 0; m < dense.size(); ++m) {
      const std::size_t i = (pointHint + m) % dense.size();
      nearest = std::min(nearest, dot(dense[i].position - sample, dense[i].position - sample));
      if (nearest <= worst) {
        pointHint = i;
        return;
      }
    }
    nearest = std::min(nearest, dot(apex.position - sample, apex.position - sample));
    for (const FanPoint& r : rim) nearest = std::min(nearest, dot(r.position - sample, r.position - sample));
    worst = std::max(worst, nearest);
  };
  for (std::size_t f = 0; f < faces && worst < bound; ++f) {
    measure((apex.position + rim[f].position + rim[f + 1].position) * (1.0 / 3));
    if (f > 0) measure((apex.position + rim[f].position) * 0.5);
  }
  return worst;
}

}  // namespace isoatlas::multires
