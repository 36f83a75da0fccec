#include "atlas/stamp_detail.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "atlas/tile_sides.h"
#include "core/error.h"

namespace isoatlas::atlas {
namespace {

// The stamp as a height field over the tangent plane at its centre: ink g in [0, 1] and its slope.
class StampField {
public:
  StampField(const Stamp& s, const Vec3& centre, const Vec3& normal) : stamp_(s), centre_(centre), normal_(normal) {
    const Vec3 worldUp = std::abs(normal.z) > 0.9 ? Vec3{0, 1, 0} : Vec3{0, 0, 1};
    up_ = worldUp - normal * dot(worldUp, normal);
    up_ = unit(up_);
    right_ = cross(up_, normal);  // right x up = normal: seen from outside, the image reads left to right
    const double w = s.image.width, h = s.image.height;
    pixel_ = 2 * s.radius / std::sqrt(w * w + h * h);
  }

  // Ink at surface point p with normal n (0 outside the disc, facing away or off the image), and
  // its slope along right_ and up_ (per mm).
  bool at(const Vec3& p, const Vec3& n, double& g, double& slopeRight, double& slopeUp) const {
    const Vec3 d = p - centre_;
    if (dot(d, d) >= stamp_.radius * stamp_.radius || dot(n, normal_) <= 0) return false;
    const double x = dot(d, right_) / pixel_ + stamp_.image.width / 2.0, y = stamp_.image.height / 2.0 - dot(d, up_) / pixel_;
    g = ink(x, y);
    slopeRight = (ink(x + 1, y) - ink(x - 1, y)) / (2 * pixel_);
    slopeUp = (ink(x, y - 1) - ink(x, y + 1)) / (2 * pixel_);
    return g > 0 || slopeRight != 0 || slopeUp != 0;
  }
  // p and n moved by the stamp; false where it does not reach.
  bool apply(Vec3& p, Vec3& n) const {
    double g, sr, su;
    if (!at(p, n, g, sr, su)) return false;
    const Vec3 moved = p - n * (stamp_.depth * g);
    n = n + (right_ * sr + up_ * su) * stamp_.depth;
    p = moved;
    return true;
  }

private:
  // Bilinear ink at image point (x, y) (pixel centres at half-integers), 0 off the image.
  double ink(double x, double y) const {
    const double fx = x - 0.5, fy = y - 0.5;
    const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
    const double tx = fx - x0, ty = fy - y0;
    auto pixel = [&](int px, int py) {
      if (px < 0 || py < 0 || px >= stamp_.image.width || py >= stamp_.image.height) return 0.0;
      const std::uint8_t* c = stamp_.image.at(px, py);
      return (stamp_.image.channels >= 3 ? 0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2] : double(c[0])) / 255;
    };
    return (1 - ty) * ((1 - tx) * pixel(x0, y0) + tx * pixel(x0 + 1, y0)) + ty * ((1 - tx) * pixel(x0, y0 + 1) + tx * pixel(x0 + 1, y0 + 1));
  }

  const Stamp& stamp_;
  Vec3 centre_, normal_, up_, right_;
  double pixel_;  // mm per image pixel
};

struct Sample {
  Vec3 position, normal;
};

// Chart c at fine texel (I, J) of a `fine`-texel grid, as the finest level triangulates the chart:
// in square (a, b), along its main diagonal when a + b is even, else the other. On the chart's
// border the samples are interpolated along the base edge from its lower-numbered vertex, so every
// chart on that edge computes the same numbers.
Sample upsample(const multires::BaseMesh& base, const Atlas& atlas, std::uint32_t c, std::uint32_t I, std::uint32_t J,
                std::uint32_t fine) {
  const std::uint32_t n = atlas.layout.chartSize, r = (fine - 1) / (n - 1), last = fine - 1;
  auto at = [&](std::uint32_t i, std::uint32_t j) { return Sample{atlas.position(c, i, j), atlas.normal(c, i, j)}; };
  auto mix = [](const Sample& a, const Sample& b, double t) {
    return Sample{a.position * (1 - t) + b.position * t, a.normal * (1 - t) + b.normal * t};
  };
  if (I % r == 0 && J % r == 0) return at(I / r, J / r);
  if (I == 0 || J == 0 || I == last || J == last) {
    const int side = J == 0 ? 0 : I == last ? 1 : J == last ? 2 : 3;
    const std::uint32_t m = side == 0 ? I : side == 1 ? J : side == 2 ? last - I : last - J;
    const TileSide s = tileSides(base, c)[side];
    const std::uint32_t canonical = s.from < s.to ? m : last - m;  // steps from the lower vertex
    const std::uint32_t k = canonical / r;
    auto coarse = [&](std::uint32_t step) {  // coarse step from the lower vertex, in this chart
      const auto ij = sideTexel(side, s.from < s.to ? step : (n - 1) - step, n);
      return at(ij[0], ij[1]);
    };
    return mix(coarse(k), coarse(k + 1), double(canonical - k * r) / r);
  }
  const std::uint32_t a = I / r, b = J / r;
  const double fx = double(I - a * r) / r, fy = double(J - b * r) / r;
  const Sample v00 = at(a, b), v10 = at(a + 1, b), v01 = at(a, b + 1), v11 = at(a + 1, b + 1);
  auto affine = [](const Sample& o, const Sample& p, const Sample& q, double s, double t) {  // o + s (p - o) + t (q - o)
    return Sample{o.position + (p.position - o.position) * s + (q.position - o.position) * t,
                  o.normal + (p.normal - o.normal) * s + (q.normal - o.normal) * t};
  };
  if ((a + b) % 2 == 0) return fx >= fy ? affine(v00, v10, v11, fx - fy, fy) : affine(v00, v11, v01, fx, fy - fx);
  return fx + fy <= 1 ? affine(v00, v10, v01, fx, fy) : affine(v11, v01, v10, 1 - fx, 1 - fy);
}

void store(const Sample& s, std::array<float, 3>& position, Normal16& normal) {
  position = {float(s.position.x), float(s.position.y), float(s.position.z)};
  normal = packNormal(s.normal);
}

}  // namespace

StampStats stampDetail(const multires::BaseMesh& base, Atlas& atlas, const Stamp& stamp) {
  const AtlasLayout& l = atlas.layout;
  require(stamp.image.width > 0 && stamp.image.height > 0, "stamp: the image is empty");
  require(std::isfinite(stamp.radius) && stamp.radius > 0, "stamp: the radius must be a positive number of mm");
  require(std::isfinite(stamp.depth) && stamp.depth != 0 && std::abs(stamp.depth) <= stamp.radius,
          "stamp: the depth must be a non-zero number of mm, at most the radius");
  require(multires::isChartSize(stamp.detailSize) && stamp.detailSize > l.chartSize,
          "stamp: the detail chart size must be 2^k + 1, above the chart size " + std::to_string(l.chartSize) + " and at most " +
              std::to_string(multires::kMaxChartSize));
  for (const DetailChart& d : atlas.details)
    require(d.size == stamp.detailSize, "stamp: the model's detail charts have " + std::to_string(d.size) +
                                            " texels a side; stamp with that size");
  require(l.charts == base.tiles.size() && !base.tiles.empty(), "stamp: the atlas does not belong to this base mesh");

  // The centre: the chart texel nearest the given point.
  StampStats stats;
  double best = std::numeric_limits<double>::infinity();
  for (std::uint32_t c = 0; c < l.charts; ++c)
    for (std::uint32_t j = 0; j < l.chartSize; ++j)
      for (std::uint32_t i = 0; i < l.chartSize; ++i) {
        const double d = norm(atlas.position(c, i, j) - stamp.at);
        if (d < best) best = d, stats.centre = atlas.position(c, i, j), stats.normal = atlas.normal(c, i, j);
      }
  require(norm(stats.normal) > 0, "stamp: the surface has no normal at the centre");
  stats.normal = unit(stats.normal);
  const StampField field(stamp, stats.centre, stats.normal);

  // Detail charts first, from the charts as they were: every tile whose chart's box comes within
  // the radius and whose upsampled chart the stamp reaches.
  const std::uint32_t fine = stamp.detailSize;
  std::vector<std::int64_t> detailOf(l.charts, -1);
  for (std::size_t k = 0; k < atlas.details.size(); ++k) detailOf[atlas.details[k].tile] = std::int64_t(k);
  for (std::uint32_t c = 0; c < l.charts; ++c) {
    Vec3 lo{1e300, 1e300, 1e300}, hi = lo * -1;
    for (std::uint32_t j = 0; j < l.chartSize; ++j)
      for (std::uint32_t i = 0; i < l.chartSize; ++i) {
        const Vec3 p = atlas.position(c, i, j);
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
      }
    Vec3 gap;
    for (int a = 0; a < 3; ++a) gap[a] = std::max({lo[a] - stats.centre[a], stats.centre[a] - hi[a], 0.0});
    if (norm(gap) >= stamp.radius) continue;
    DetailChart made{c, fine, {}, {}};
    const bool existing = detailOf[c] >= 0;
    DetailChart& detail = existing ? atlas.details[std::size_t(detailOf[c])] : made;
    if (!existing) {
      detail.positions.resize(std::size_t(fine) * fine), detail.normals.resize(std::size_t(fine) * fine);
      for (std::uint32_t J = 0; J < fine; ++J)
        for (std::uint32_t I = 0; I < fine; ++I)
          store(upsample(base, atlas, c, I, J, fine), detail.positions[std::size_t(J) * fine + I], detail.normals[std::size_t(J) * fine + I]);
    }
    std::uint64_t changed = 0;
    for (std::size_t t = 0; t < detail.positions.size(); ++t) {
      const auto& q = detail.positions[t];
      Vec3 p{q[0], q[1], q[2]}, n = unpackNormal(detail.normals[t]);
      if (field.apply(p, n)) ++changed, store({p, n}, detail.positions[t], detail.normals[t]);
    }
    if (changed == 0) continue;  // near, but the stamp does not reach it
    stats.detailTexelsChanged += changed;
    ++stats.detailTiles;
    if (!existing) atlas.details.push_back(std::move(made));
  }
  std::sort(atlas.details.begin(), atlas.details.end(), [](const DetailChart& a, const DetailChart& b) { return a.tile < b.tile; });

  // Then the tiles' own charts.
  for (std::uint32_t c = 0; c < l.charts; ++c)
    for (std::uint32_t j = 0; j < l.chartSize; ++j)
      for (std::uint32_t i = 0; i < l.chartSize; ++i) {
        const std::size_t at = l.texel(c, i, j);
        Vec3 p = atlas.position(c, i, j), n = atlas.normal(c, i, j);
        if (field.apply(p, n)) ++stats.texelsChanged, store({p, n}, atlas.positions[at], atlas.normals[at]);
      }
  return stats;
}

}  // namespace isoatlas::atlas
