// A small ch2-like head for the viewer's tests: 1.5 mm voxels centred on the world origin (RAS), a
// bright ellipsoid "brain" (100) inside a brighter shell "skull" (160) in a dark background (20),
// mild noise. The brain's truth comes with it.
#pragma once
#include <algorithm>
#include <random>
#include <vector>

#include "core/volume.h"

namespace isoatlas::test {

struct HeadPhantom {
  Volume image, brain;  // brain: uint8 truth
  // Brain ellipsoid semi-axes (mm); the skull is 6 mm further out.
  static constexpr double kRx = 21, kRy = 27, kRz = 18;
};

inline HeadPhantom headPhantom() {
  const std::array<std::int64_t, 3> dims{44, 52, 40};
  HeadPhantom h{Volume::zeros(dims, ScalarType::Int16), Volume::zeros(dims, ScalarType::UInt8)};
  for (Volume* v : {&h.image, &h.brain}) {
    v->spacing = {1.5, 1.5, 1.5};
    v->origin = {-1.5 * double(dims[0] - 1) / 2, -1.5 * double(dims[1] - 1) / 2, -1.5 * double(dims[2] - 1) / 2};
  }
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 4);
  for (std::int64_t k = 0; k < dims[2]; ++k)
    for (std::int64_t j = 0; j < dims[1]; ++j)
      for (std::int64_t i = 0; i < dims[0]; ++i) {
        const Vec3 w = h.image.indexToWorld({double(i), double(j), double(k)});
        auto inside = [&](double grow) {
          const double x = w.x / (HeadPhantom::kRx + grow), y = w.y / (HeadPhantom::kRy + grow), z = w.z / (HeadPhantom::kRz + grow);
          return x * x + y * y + z * z < 1;
        };
        const bool brain = inside(0);
        h.brain.setValue(h.brain.index(i, j, k), brain);
        h.image.setValue(h.image.index(i, j, k), (brain ? 100 : inside(6) ? 160 : 20) + noise(rng));
      }
  return h;
}

// Whether p lies within `radius` of the polyline through `path`: inside a brush stroke dragged there.
inline bool inStroke(const Vec3& p, const std::vector<Vec3>& path, double radius) {
  for (std::size_t n = 0; n + 1 < path.size(); ++n) {
    const Vec3 ab = path[n + 1] - path[n];
    const double t = std::clamp(dot(p - path[n], ab) / std::max(1e-12, dot(ab, ab)), 0.0, 1.0);
    if (norm(p - (path[n] + ab * t)) < radius) return true;
  }
  return false;
}

}  // namespace isoatlas::test
