// The level-set tests' phantom: a noisy solid torus with known truth, and Dice between masks.
#pragma once
#include <cmath>
#include <random>

#include "core/vec.h"
#include "core/volume.h"

namespace isoatlas::levelset {

inline double dice(const Volume& a, const Volume& b) {
  std::int64_t both = 0, sa = 0, sb = 0;
  for (std::size_t n = 0; n < a.voxelCount(); ++n) {
    const bool x = a.value(n) > 0, y = b.value(n) > 0;
    both += x && y;
    sa += x;
    sb += y;
  }
  return sa + sb ? 2.0 * double(both) / double(sa + sb) : 1.0;
}

// A solid torus (genus 1) of intensity 100 in a background of 40, with Gaussian noise of sigma 12.
struct Phantom {
  Volume image, truth;
  Vec3 seedA, seedB;
};
// width: 64, or down to 58, where the torus meets the volume's +x edge (pages cut off in x).
inline Phantom torusPhantom(std::int64_t width = 64) {
  const std::array<std::int64_t, 3> dims{width, 60, 40};
  Phantom p{Volume::zeros(dims, ScalarType::Float32), Volume::zeros(dims, ScalarType::UInt8), {}, {}};
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 12);
  const double cx = 32, cy = 30, cz = 20, R = 18, r = 7;
  for (std::int64_t z = 0; z < dims[2]; ++z)
    for (std::int64_t y = 0; y < dims[1]; ++y)
      for (std::int64_t x = 0; x < dims[0]; ++x) {
        const double q = std::hypot(double(x) - cx, double(y) - cy) - R;
        const bool in = q * q + (double(z) - cz) * (double(z) - cz) < r * r;
        p.truth.setValue(p.truth.index(x, y, z), in);
        p.image.setValue(p.image.index(x, y, z), (in ? 100 : 40) + noise(rng));
      }
  p.seedA = {cx + R, cy, cz};
  p.seedB = {cx - R, cy, cz};
  return p;
}

}  // namespace isoatlas::levelset
