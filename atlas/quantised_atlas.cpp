#include "atlas/quantised_atlas.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "atlas/separate_codes.h"
#include "atlas/unfold_codes.h"
#include "atlas/tile_sides.h"
#include "core/deflate.h"
#include "core/error.h"

namespace isoatlas::atlas {

std::array<std::uint8_t, 2> encodeOctahedral(const Vec3& normal) {
  const double l1 = std::abs(normal.x) + std::abs(normal.y) + std::abs(normal.z);
  double x = l1 > 0 ? normal.x / l1 : 0, y = l1 > 0 ? normal.y / l1 : 0;
  if (l1 > 0 && normal.z < 0) {  // the lower half folded over the diagonals
    const double fx = (1 - std::abs(y)) * (x >= 0 ? 1 : -1), fy = (1 - std::abs(x)) * (y >= 0 ? 1 : -1);
    x = fx, y = fy;
  }
  auto code = [](double v) { return std::uint8_t(std::lround(std::clamp((v + 1) * 127.5, 0.0, 255.0))); };
  return {code(x), code(y)};
}

Vec3 decodeOctahedral(const std::array<std::uint8_t, 2>& code) {
  double x = code[0] / 127.5 - 1, y = code[1] / 127.5 - 1;
  const double z = 1 - std::abs(x) - std::abs(y);
  if (z < 0) {
    const double fx = (1 - std::abs(y)) * (x >= 0 ? 1 : -1), fy = (1 - std::abs(x)) * (y >= 0 ? 1 : -1);
    x = fx, y = fy;
  }
  const Vec3 n{x, y, z};
  return n * (1 / norm(n));
}

std::vector<QuantisedChart> quantiseAtlas(const Atlas& atlas, const multires::BaseMesh& base, SeparatedTexels* separated,
                                          Atlas* decoded) {
  const std::uint32_t n = atlas.layout.chartSize;
  std::vector<QuantisedChart> charts(atlas.layout.charts);
  tbb::parallel_for(std::uint32_t(0), atlas.layout.charts, [&](std::uint32_t c) {  // charts apart: on every core
    QuantisedChart& q = charts[c];
    std::array<float, 3> hi{};
    q.lo = hi = atlas.positions[atlas.layout.texel(c, 0, 0)];
    for (std::uint32_t j = 0; j < n; ++j)
      for (std::uint32_t i = 0; i < n; ++i) {
        const auto& p = atlas.positions[atlas.layout.texel(c, i, j)];
        for (int a = 0; a < 3; ++a) q.lo[a] = std::min(q.lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
      }
    for (int a = 0; a < 3; ++a) q.step[a] = (hi[a] - q.lo[a]) / float(kLargestPositionCode);
    for (std::uint32_t j = 0; j < n; ++j)
      for (std::uint32_t i = 0; i < n; ++i) {
        const std::size_t at = atlas.layout.texel(c, i, j);
        std::array<std::uint16_t, 3> code{};
        for (int a = 0; a < 3; ++a)
          if (q.step[a] > 0)
            code[a] = std::uint16_t(std::clamp(std::lround((atlas.positions[at][a] - q.lo[a]) / q.step[a]), 0L, long(kLargestPositionCode)));
        q.positions.push_back(code);
        q.normals.push_back(encodeOctahedral(unpackNormal(atlas.normals[at])));
      }
  });
  Atlas decodedHere;
  Atlas& decode = decoded ? *decoded : decodedHere;
  decode.layout = atlas.layout;
  dequantiseAtlas(charts, base, decode);  // once: the two below keep it as they move codes
  unfoldRoundedTexels(atlas, charts, decode);
  const SeparatedTexels moved = separateJoinedTexels(atlas, base, charts, decode);
  if (separated) *separated = moved;
  return charts;
}

void dequantiseAtlas(const std::vector<QuantisedChart>& charts, const multires::BaseMesh& base, Atlas& atlas) {
  const std::uint32_t n = atlas.layout.chartSize;
  const std::size_t texels = std::size_t(atlas.layout.width()) * atlas.layout.height();
  atlas.positions.assign(texels, {0, 0, 0});
  atlas.normals.assign(texels, {0, 0, 0});
  tbb::parallel_for(std::size_t(0), charts.size(), [&](std::size_t c) {  // charts apart: on every core
    const QuantisedChart& q = charts[c];
    for (std::uint32_t j = 0; j < n; ++j)
      for (std::uint32_t i = 0; i < n; ++i) {
        const std::size_t k = std::size_t(j) * n + i, at = atlas.layout.texel(std::uint32_t(c), i, j);
        atlas.positions[at] = decodePosition(q, q.positions[k]);
        atlas.normals[at] = packNormal(decodeOctahedral(q.normals[k]));
      }
  });
  const auto across = sidesAcross(base);
  for (std::uint32_t c = 0; c < charts.size(); ++c)
    for (int s = 0; s < 4; ++s) {
      const SideAcross other = across[c][s];
      if (other.tile == kNoTile || other.tile < c) continue;
      for (std::uint32_t m = 1; m + 1 < n; ++m) {
        const auto ij = sideTexel(s, m, n), kl = sideTexel(other.side, n - 1 - m, n);
        const std::size_t from = atlas.layout.texel(c, ij[0], ij[1]), to = atlas.layout.texel(other.tile, kl[0], kl[1]);
        atlas.positions[to] = atlas.positions[from];
        atlas.normals[to] = atlas.normals[from];
      }
    }
  // Corners: each base vertex's from the first chart that has it, copied into the others; within
  // that chart's quantisation of the base vertex it is the base vertex (as makeAtlas made it), else
  // a stamp moved it and it stays where the chart puts it.
  std::vector<std::size_t> cornerFrom(base.vertexCount(), ~std::size_t(0));
  for (std::uint32_t c = 0; c < charts.size(); ++c) {
    const auto sides = tileSides(base, c);
    for (int s = 0; s < 4; ++s) {
      const auto ij = sideTexel(s, 0, n);
      const std::size_t at = atlas.layout.texel(c, ij[0], ij[1]);
      std::size_t& from = cornerFrom[sides[s].from];
      if (from == ~std::size_t(0)) {
        from = at;
        const Vec3& v = base.positions[sides[s].from];
        const auto& p = atlas.positions[at];
        const auto& step = charts[c].step;
        const double halfStep = 0.5 * std::hypot(double(step[0]), double(step[1]), double(step[2]));
        if (std::hypot(p[0] - v.x, p[1] - v.y, p[2] - v.z) <= halfStep * 1.001) atlas.positions[at] = {float(v.x), float(v.y), float(v.z)};
      }
      atlas.positions[at] = atlas.positions[from];
      atlas.normals[at] = atlas.normals[from];
    }
  }
}

double largestQuantisationError(const Atlas& atlas, const Atlas& decoded) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, atlas.positions.size()), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double worst) {
        for (std::size_t t = r.begin(); t != r.end(); ++t) {
          const auto &a = atlas.positions[t], &b = decoded.positions[t];
          worst = std::max(worst, std::hypot(double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2]));
        }
        return worst;
      },
      [](double a, double b) { return std::max(a, b); });
}

bool decodesTo(const std::vector<QuantisedChart>& charts, const multires::BaseMesh& base, const Atlas& atlas) {
  if (charts.empty() || charts.size() != atlas.layout.charts) return false;
  Atlas decoded;
  decoded.layout = atlas.layout;
  dequantiseAtlas(charts, base, decoded);
  return decoded.positions == atlas.positions && decoded.normals == atlas.normals;
}

namespace {

// Channel c of texel k's code as its left, upper and upper-left neighbours predict it (the
// parallelogram rule, in the code's own width: it wraps, and the residual unwraps it exactly).
template <class Code, std::size_t C>
Code predicted(const std::vector<std::array<Code, C>>& codes, std::uint32_t n, std::size_t k, int c) {
  const std::size_t i = k % n, j = k / n;
  const Code left = i > 0 ? codes[k - 1][c] : 0, up = j > 0 ? codes[k - n][c] : 0;
  return i > 0 && j > 0 ? Code(left + up - codes[k - n - 1][c]) : i > 0 ? left : up;
}

// A residual as an unsigned code of the same width, small either side of zero: 0, -1, 1, -2, ...
template <class Code>
Code zigzag(Code r) {
  return Code((r << 1) ^ (std::make_signed_t<Code>(r) < 0 ? Code(~Code(0)) : Code(0)));
}
template <class Code>
Code unzigzag(Code z) {
  return Code((z >> 1) ^ -(z & 1));
}

// A chart's codes of one kind (C channels of Code) as sizeof(Code) x C byte planes of n x n, plane
// b * C + c holding byte b of channel c's zigzagged residuals; fromPlanes undoes it.
template <class Code, std::size_t C>
void toPlanes(const std::vector<std::array<Code, C>>& codes, std::uint32_t n, std::uint8_t* planes) {
  const std::size_t texels = std::size_t(n) * n;
  for (std::size_t c = 0; c < C; ++c)
    for (std::size_t k = 0; k < texels; ++k) {
      const Code z = zigzag(Code(codes[k][c] - predicted(codes, n, k, int(c))));
      for (std::size_t b = 0; b < sizeof(Code); ++b) planes[(b * C + c) * texels + k] = std::uint8_t(z >> (8 * b));
    }
}
template <class Code, std::size_t C>
void fromPlanes(const std::uint8_t* planes, std::uint32_t n, std::vector<std::array<Code, C>>& codes) {
  const std::size_t texels = std::size_t(n) * n;
  codes.assign(texels, {});
  for (std::size_t c = 0; c < C; ++c)
    for (std::size_t k = 0; k < texels; ++k) {
      Code z = 0;
      for (std::size_t b = 0; b < sizeof(Code); ++b) z = Code(z | planes[(b * C + c) * texels + k] << (8 * b));
      codes[k][c] = Code(predicted(codes, n, k, int(c)) + unzigzag(z));
    }
}

}  // namespace

std::vector<std::uint8_t> packChartCodes(const QuantisedChart& chart, std::uint32_t n) {
  const std::size_t texels = std::size_t(n) * n;
  // Planes: the positions' residuals' low bytes of x, y, z, their high bytes, then the normals' two.
  std::vector<std::uint8_t> planes(texels * 8);
  toPlanes(chart.positions, n, planes.data());
  toPlanes(chart.normals, n, planes.data() + 6 * texels);
  return deflateBytes(planes.data(), planes.size(), 6, "model file: a chart's codes");
}

bool unpackChartCodes(const std::uint8_t* bytes, std::size_t size, std::uint32_t n, QuantisedChart& chart) {
  const std::size_t texels = std::size_t(n) * n;
  std::vector<std::uint8_t> planes(texels * 8);
  if (!inflateExactly(bytes, size, planes.data(), planes.size())) return false;
  fromPlanes(planes.data(), n, chart.positions);
  fromPlanes(planes.data() + 6 * texels, n, chart.normals);
  return true;
}

}  // namespace isoatlas::atlas
