#include "levelset/probe.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace isoatlas::levelset {

ProbeResult probeSphere(const Volume& v, const Vec3& c, double radius) {
  require(std::isfinite(radius) && radius > 0, "probe radius must be > 0");
  for (int a = 0; a < 3; ++a)
    require(std::isfinite(c[a]) && c[a] >= 0 && c[a] <= double(v.dims[a] - 1),
            "probe centre (" + std::to_string(c.x) + ", " + std::to_string(c.y) + ", " + std::to_string(c.z) +
                ") lies outside the volume (0..dims-1 on each axis)");
  ProbeResult r;
  double sum = 0, sumSq = 0;
  auto range = [&](int a) {
    return std::pair{std::max<std::int64_t>(0, std::int64_t(std::ceil(c[a] - radius))),
                     std::min<std::int64_t>(v.dims[a] - 1, std::int64_t(std::floor(c[a] + radius)))};
  };
  const auto [x0, x1] = range(0);
  const auto [y0, y1] = range(1);
  const auto [z0, z1] = range(2);
  for (std::int64_t z = z0; z <= z1; ++z)
    for (std::int64_t y = y0; y <= y1; ++y)
      for (std::int64_t x = x0; x <= x1; ++x) {
        const double d2 = (double(x) - c.x) * (double(x) - c.x) + (double(y) - c.y) * (double(y) - c.y) +
                          (double(z) - c.z) * (double(z) - c.z);
        if (d2 > radius * radius) continue;
        const double value = v.at(x, y, z);
        sum += value;
        sumSq += value * value;
        ++r.voxels;
      }
  require(r.voxels > 0, "the probe sphere holds no voxel (radius too small?)");
  r.mean = sum / double(r.voxels);
  r.std = std::sqrt(std::max(0.0, sumSq / double(r.voxels) - r.mean * r.mean));
  return r;
}

}  // namespace isoatlas::levelset
