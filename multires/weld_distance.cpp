#include "multires/weld_distance.h"

#include <algorithm>
#include <limits>

namespace isoatlas::multires {

double weldDistance2(const FanPoint& apex, std::span<const FanPoint> rim, std::span<const FanPoint> dense,
                     double bound) {
  const std::size_t faces = rim.size() < 2 ? 0 : rim.size() - 1;
  if (faces == 0) return 0;
  double worst = 0;
  // Dense vertices to their images, each located from the face that held the last one (the list
  // runs face by face, so most searches end at the first try).
  auto fanFace = [&](std::size_t f) { return std::array<Vec2, 3>{apex.plane, rim[f].plane, rim[f + 1].plane}; };
  std::size_t faceHint = 0;
  for (const FanPoint& p : dense) {
    const TriangleHit hit = locateInTriangles(p.plane, faces, fanFace, faceHint);
    if (hit.triangle == kNoTriangleHit) return std::numeric_limits<double>::infinity();  // a flat fan
    faceHint = hit.triangle;
    const Vec3 image = apex.position * hit.bary[0] + rim[hit.triangle].position * hit.bary[1] +
                       rim[hit.triangle + 1].position * hit.bary[2];
    worst = std::max(worst, dot(image - p.position, image - p.position));
    if (worst >= bound) return worst;
  }
  // The fan to the dense vertices, at the new faces' centroids and the new spokes' midpoints; a
  // search stops at a vertex nearer than the worst so far, which cannot raise it.
  std::size_t pointHint = 0;
  auto measure = [&](const Vec3& sample) {
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t m = 0, i = pointHint; m < dense.size(); ++m, i = nextRound(i, dense.size())) {
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
