#include "render/slice_render.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace isoatlas::render {
namespace {

// Trilinear sample of at(i, j, k) at a continuous voxel index; outside the volume reads as NaN.
template <class At>
double sample(const std::array<std::int64_t, 3>& dims, const Vec3& p, const At& at) {
  const double x = p.x, y = p.y, z = p.z;
  if (x < -0.5 || y < -0.5 || z < -0.5 || x > double(dims[0]) - 0.5 || y > double(dims[1]) - 0.5 || z > double(dims[2]) - 0.5)
    return std::numeric_limits<double>::quiet_NaN();
  auto clampi = [](double t, std::int64_t n) { return std::clamp<std::int64_t>(std::int64_t(std::floor(t)), 0, n - 1); };
  const std::int64_t i0 = clampi(x, dims[0]), j0 = clampi(y, dims[1]), k0 = clampi(z, dims[2]);
  const std::int64_t i1 = std::min(i0 + 1, dims[0] - 1), j1 = std::min(j0 + 1, dims[1] - 1), k1 = std::min(k0 + 1, dims[2] - 1);
  const double fx = std::clamp(x - double(i0), 0.0, 1.0), fy = std::clamp(y - double(j0), 0.0, 1.0),
               fz = std::clamp(z - double(k0), 0.0, 1.0);
  auto lerp = [](double a, double b, double t) { return a + (b - a) * t; };
  const double c00 = lerp(at(i0, j0, k0), at(i1, j0, k0), fx), c10 = lerp(at(i0, j1, k0), at(i1, j1, k0), fx);
  const double c01 = lerp(at(i0, j0, k1), at(i1, j0, k1), fx), c11 = lerp(at(i0, j1, k1), at(i1, j1, k1), fx);
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

void blend(double rgb[3], const std::uint8_t colour[3], double weight) {
  for (int c = 0; c < 3; ++c) rgb[c] = (1 - weight) * rgb[c] + weight * colour[c];
}

}  // namespace

IntensityWindow percentileWindow(const Volume& volume, double lowPercentile, double highPercentile) {
  std::vector<double> values;
  const std::size_t count = volume.voxelCount(), stride = std::max<std::size_t>(1, count / 200000);
  for (std::size_t n = 0; n < count; n += stride) values.push_back(volume.value(n));
  auto percentile = [&](double p) {
    const std::size_t k = std::min(values.size() - 1, std::size_t(p / 100 * double(values.size() - 1)));
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
    return values[k];
  };
  return {percentile(lowPercentile), percentile(highPercentile)};
}

SliceLayout::SliceLayout(const Volume& volume, const Vec3& centre, int panelSize) : centre_(centre), size_(panelSize) {
  Vec3 lo, hi;
  worldBounds(volume, lo, hi);
  mid_ = (lo + hi) * 0.5;
  for (int panel = 0; panel < 3; ++panel) {
    const Plane& pl = kPlanes[panel];
    mmPerPixel_[panel] = std::max(hi[pl.right] - lo[pl.right], hi[pl.up] - lo[pl.up]) / panelSize;
  }
}

Vec3 SliceLayout::world(int panel, double px, double py) const {
  const Plane& pl = kPlanes[panel];
  Vec3 w = centre_;
  w[pl.right] = mid_[pl.right] + pl.rightSign * (px - size_ / 2.0) * mmPerPixel_[panel];
  w[pl.up] = mid_[pl.up] + (size_ / 2.0 - py) * mmPerPixel_[panel];
  return w;
}

std::array<double, 2> SliceLayout::pixel(int panel, const Vec3& w) const {
  const Plane& pl = kPlanes[panel];
  return {size_ / 2.0 + pl.rightSign * (w[pl.right] - mid_[pl.right]) / mmPerPixel_[panel],
          size_ / 2.0 - (w[pl.up] - mid_[pl.up]) / mmPerPixel_[panel]};
}

VoxelField pagedField(const levelset::LevelSet& levelSet) {
  const float* pool = levelSet.phiPoolOnHost();
  const levelset::PageManager* pages = &levelSet.pages();
  return [pool, pages](std::int64_t i, std::int64_t j, std::int64_t k) { return pool[pages->poolTexel(i, j, k)]; };
}

Vec3 volumeCentre(const Volume& v) {
  return v.indexToWorld({double(v.dims[0] - 1) / 2, double(v.dims[1] - 1) / 2, double(v.dims[2] - 1) / 2});
}

Image renderSlices(const Volume& volume, const Vec3& centre, const SliceOptions& opt) {
  const IntensityWindow window = opt.window ? *opt.window : percentileWindow(volume, opt.lowPercentile, opt.highPercentile);
  const double scale = window.high > window.low ? 255.0 / (window.high - window.low) : 1.0;
  const SliceLayout layout(volume, centre, opt.panelSize);
  const int n = opt.panelSize;
  Image img(3 * n, n, 3);
  // phi per pixel first: the contour is where it changes sign between neighbouring pixels.
  std::vector<float> phi(opt.phi ? std::size_t(3) * n * n : 0, std::numeric_limits<float>::quiet_NaN());
  const std::uint8_t positive[3] = {60, 140, 255}, negative[3] = {255, 60, 60}, cross[3] = {90, 220, 90};
  tbb::parallel_for(0, 3 * n, [&](int row) {
    const int panel = row / n, py = row % n;
    for (int px = 0; px < n; ++px) {
      const Vec3 ijk = volume.worldToIndex(layout.world(panel, px + 0.5, py + 0.5));
      const double s = sample(volume.dims, ijk, [&](std::int64_t i, std::int64_t j, std::int64_t k) { return volume.at(i, j, k); });
      const double g = std::isnan(s) ? 0 : std::clamp((s - window.low) * scale, 0.0, 255.0);
      double rgb[3] = {g, g, g};
      if (opt.mask && maskAt(*opt.mask, ijk)) blend(rgb, opt.maskColour, 0.45);
      if (opt.speed && !std::isnan(s)) {
        const double data = opt.speed->width - std::fabs(s - opt.speed->target);
        blend(rgb, data > 0 ? positive : negative, 0.35 * std::min(1.0, std::fabs(data) / opt.speed->width));
      }
      if (opt.phi) phi[std::size_t(panel) * n * n + std::size_t(py) * n + px] = float(sample(volume.dims, ijk, opt.phi));
      for (int c = 0; c < 3; ++c) img.at(panel * n + px, py)[c] = std::uint8_t(rgb[c] + 0.5);
    }
  });
  for (int panel = 0; panel < 3 && (opt.phi || opt.crosshair); ++panel) {
    const auto at = layout.pixel(panel, centre);
    const int cx = int(std::floor(at[0])), cy = int(std::floor(at[1]));
    for (int py = 0; py < n; ++py)
      for (int px = 0; px < n; ++px) {
        std::uint8_t* out = img.at(panel * n + px, py);
        if (opt.crosshair && (px == cx || py == cy) && (px + py) % 2 == 0)
          for (int c = 0; c < 3; ++c) out[c] = cross[c];
        if (!opt.phi) continue;
        const float* p = phi.data() + std::size_t(panel) * n * n;
        const float here = p[std::size_t(py) * n + px];
        const float right = px + 1 < n ? p[std::size_t(py) * n + px + 1] : here;
        const float below = py + 1 < n ? p[std::size_t(py + 1) * n + px] : here;
        if ((here > 0) != (right > 0) || (here > 0) != (below > 0))
          if (!std::isnan(here) && !std::isnan(right) && !std::isnan(below))
            for (int c = 0; c < 3; ++c) out[c] = kContourColour[c];
      }
  }
  return img;
}

}  // namespace isoatlas::render
