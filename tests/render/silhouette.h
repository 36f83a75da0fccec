// A sphere's true silhouette on a camera's picture, for the renderers' tests.
#pragma once
#include <cmath>
#include <utility>

#include "core/image.h"
#include "render/camera.h"

namespace isoatlas::test {

// Whether a pixel differs from a white background.
inline bool drawn(const Image& image, int x, int y) { return image.at(x, y)[0] < 250 || image.at(x, y)[2] < 250; }

// Pixels where the picture and the true silhouette of a sphere (a ray through the pixel's centre
// meets it) disagree, and the silhouette's pixel count.
inline std::pair<std::int64_t, std::int64_t> silhouetteMismatch(const Image& image, const render::Camera& c, const Vec3& centre, double radius) {
  std::int64_t wrong = 0, inside = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const Vec3 d = c.rayThrough(x + 0.5, y + 0.5);
      const Vec3 m = c.eye - centre;
      const double b = dot(m, d), q = dot(m, m) - radius * radius;
      const bool hit = b * b - q >= 0 && -b + std::sqrt(std::max(b * b - q, 0.0)) > 0;
      inside += hit;
      wrong += hit != drawn(image, x, y);
    }
  return {wrong, inside};
}

// Pixels whose ray passes within radius - margin of a sphere's centre (well inside its silhouette)
// that the picture leaves as background: rays that slipped through the surface.
inline std::int64_t holesInside(const Image& image, const render::Camera& c, const Vec3& centre, double radius, double margin) {
  std::int64_t holes = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const Vec3 d = c.rayThrough(x + 0.5, y + 0.5), m = centre - c.eye;
      const double along = dot(m, d), miss2 = dot(m, m) - along * along;  // squared distance from the ray
      holes += along > 0 && miss2 < (radius - margin) * (radius - margin) && !drawn(image, x, y);
    }
  return holes;
}

}  // namespace isoatlas::test
