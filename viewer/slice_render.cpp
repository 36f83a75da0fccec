#include "viewer/slice_render.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace isoatlas::viewer {
namespace {

// Trilinear sample at a continuous voxel index; outside the volume reads as NaN (drawn black).
double sample(const Volume& v, const Vec3& p) {
  const double x = p.x, y = p.y, z = p.z;
  if (x < -0.5 || y < -0.5 || z < -0.5 || x > double(v.dims[0]) - 0.5 || y > double(v.dims[1]) - 0.5 ||
      z > double(v.dims[2]) - 0.5)
    return std::numeric_limits<double>::quiet_NaN();
  auto clampi = [](double t, std::int64_t n) { return std::clamp<std::int64_t>(std::int64_t(std::floor(t)), 0, n - 1); };
  const std::int64_t i0 = clampi(x, v.dims[0]), j0 = clampi(y, v.dims[1]), k0 = clampi(z, v.dims[2]);
  const std::int64_t i1 = std::min(i0 + 1, v.dims[0] - 1), j1 = std::min(j0 + 1, v.dims[1] - 1),
                     k1 = std::min(k0 + 1, v.dims[2] - 1);
  const double fx = std::clamp(x - double(i0), 0.0, 1.0), fy = std::clamp(y - double(j0), 0.0, 1.0),
               fz = std::clamp(z - double(k0), 0.0, 1.0);
  auto lerp = [](double a, double b, double t) { return a + (b - a) * t; };
  const double c00 = lerp(v.at(i0, j0, k0), v.at(i1, j0, k0), fx), c10 = lerp(v.at(i0, j1, k0), v.at(i1, j1, k0), fx);
  const double c01 = lerp(v.at(i0, j0, k1), v.at(i1, j0, k1), fx), c11 = lerp(v.at(i0, j1, k1), v.at(i1, j1, k1), fx);
  return lerp(lerp(c00, c10, fy), lerp(c01, c11, fy), fz);
}

bool maskAt(const Volume& m, const Vec3& p) {
  const auto i = std::int64_t(std::lround(p.x)), j = std::int64_t(std::lround(p.y)), k = std::int64_t(std::lround(p.z));
  if (i < 0 || j < 0 || k < 0 || i >= m.dims[0] || j >= m.dims[1] || k >= m.dims[2]) return false;
  return m.at(i, j, k) > 0;
}

// World-space extent of the volume: the box around its eight corners.
void worldBounds(const Volume& v, Vec3& lo, Vec3& hi) {
  lo = {1e300, 1e300, 1e300};
  hi = {-1e300, -1e300, -1e300};
  for (int c = 0; c < 8; ++c) {
    const Vec3 ijk{(c & 1) ? double(v.dims[0] - 1) : 0.0, (c & 2) ? double(v.dims[1] - 1) : 0.0,
                   (c & 4) ? double(v.dims[2] - 1) : 0.0};
    const Vec3 w = v.indexToWorld(ijk);
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], w[a]), hi[a] = std::max(hi[a], w[a]);
  }
}

}  // namespace

Vec3 volumeCentre(const Volume& v) {
  return v.indexToWorld({double(v.dims[0] - 1) / 2, double(v.dims[1] - 1) / 2, double(v.dims[2] - 1) / 2});
}

Image renderSlices(const Volume& volume, const Vec3& centre, const SliceOptions& opt) {
  // Window from percentiles of a strided sample of the voxels.
  std::vector<double> values;
  const std::size_t count = volume.voxelCount(), stride = std::max<std::size_t>(1, count / 200000);
  for (std::size_t n = 0; n < count; n += stride) values.push_back(volume.value(n));
  auto percentile = [&](double p) {
    const std::size_t k = std::min(values.size() - 1, std::size_t(p / 100 * double(values.size() - 1)));
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
    return values[k];
  };
  const double lo = percentile(opt.lowPercentile), hi = percentile(opt.highPercentile);
  const double scale = hi > lo ? 255.0 / (hi - lo) : 1.0;

  Vec3 wlo, whi;
  worldBounds(volume, wlo, whi);
  const int n = opt.panelSize;
  Image img(3 * n, n, 3);
  // Each panel: screen right/up as world axes. Radiological: screen right = patient left (-x).
  struct Plane { int right, up; double rightSign; };
  const Plane planes[3] = {{0, 1, -1}, {0, 2, -1}, {1, 2, 1}};  // axial (x,y), coronal (x,z), sagittal (y,z)
  for (int panel = 0; panel < 3; ++panel) {
    const Plane& pl = planes[panel];
    const double extent = std::max(whi[pl.right] - wlo[pl.right], whi[pl.up] - wlo[pl.up]);
    const double mmPerPixel = extent / n;
    for (int py = 0; py < n; ++py) {
      for (int px = 0; px < n; ++px) {
        Vec3 w = centre;
        w[pl.right] = (wlo[pl.right] + whi[pl.right]) / 2 + pl.rightSign * (px + 0.5 - n / 2.0) * mmPerPixel;
        w[pl.up] = (wlo[pl.up] + whi[pl.up]) / 2 + (n / 2.0 - py - 0.5) * mmPerPixel;
        const Vec3 ijk = volume.worldToIndex(w);
        const double s = sample(volume, ijk);
        const double g = std::isnan(s) ? 0 : std::clamp((s - lo) * scale, 0.0, 255.0);
        std::uint8_t* out = img.at(panel * n + px, py);
        double rgb[3] = {g, g, g};
        if (opt.mask && maskAt(*opt.mask, ijk))
          for (int c = 0; c < 3; ++c) rgb[c] = 0.55 * g + 0.45 * opt.maskColour[c];
        for (int c = 0; c < 3; ++c) out[c] = std::uint8_t(rgb[c] + 0.5);
      }
    }
  }
  return img;
}

}  // namespace isoatlas::viewer
