// Atlas: one N x N geometry-image chart per tile (positions and normals of the dense surface at
// the texels of the tile's unit square), packed row by row into one image. Chart c's texel (i, j)
// is a point of the tile's unit square near (i, j) / (N - 1), placed there by atlas/relax_chart.h
// (exactly there with --relax-sweeps 0): i runs from corner p towards s, j from p towards r
// (BaseMesh::chartToTriangle); the texels form a grid of convex quads over the square. Positions
// are floats in world millimetres; normals unit vectors stored as three signed 16-bit normalised
// integers (GL's RGB16_SNORM).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/vec.h"

namespace isoatlas::atlas {

// Where the charts lie: `columns` x `rows` slots of chartSize texels a side, chart c in slot
// (c % columns, c / columns), the image's top-left slot first.
struct AtlasLayout {
  std::uint32_t chartSize = 0, charts = 0, columns = 0, rows = 0;
  std::uint32_t width() const { return columns * chartSize; }
  std::uint32_t height() const { return rows * chartSize; }
  // Texel (i, j) of chart c as an index into the image (row-major).
  std::size_t texel(std::uint32_t c, std::uint32_t i, std::uint32_t j) const {
    return (std::size_t(c / columns) * chartSize + j) * width() + std::size_t(c % columns) * chartSize + i;
  }
  // Chart texels over all texels of the image.
  double efficiency() const {
    return charts == 0 ? 0 : double(charts) / (double(columns) * rows);
  }
};

using Normal16 = std::array<std::int16_t, 3>;
inline Normal16 packNormal(const Vec3& n) {
  const double length = norm(n);
  const Vec3 u = length > 0 ? n * (1 / length) : Vec3{0, 0, 1};
  auto q = [](double x) { return std::int16_t(std::lround(std::clamp(x, -1.0, 1.0) * 32767)); };
  return {q(u.x), q(u.y), q(u.z)};
}
inline Vec3 unpackNormal(const Normal16& n) {
  auto f = [](std::int16_t x) { return std::max(double(x) / 32767, -1.0); };
  return {f(n[0]), f(n[1]), f(n[2])};
}

// A finer chart of one tile, where fine detail was stamped (the paper's Fig. 10): size x size
// texels (2^k + 1, finer than the atlas's charts), texel (i, j) at chart texel (i, j) (N - 1) /
// (size - 1) (interpolated between the chart's texels, then stamped), row-major. Its borders agree bit for bit with the detail charts across them;
// where a tile without one lies across, the border carries no detail (it lies on the coarse border).
struct DetailChart {
  std::uint32_t tile = 0, size = 0;
  std::vector<std::array<float, 3>> positions;
  std::vector<Normal16> normals;
  Vec3 position(std::uint32_t i, std::uint32_t j) const {
    const auto& p = positions[std::size_t(j) * size + i];
    return {p[0], p[1], p[2]};
  }
  Vec3 normal(std::uint32_t i, std::uint32_t j) const { return unpackNormal(normals[std::size_t(j) * size + i]); }
};

struct Atlas {
  AtlasLayout layout;
  std::vector<std::array<float, 3>> positions;  // width x height; zero outside the charts
  std::vector<Normal16> normals;                // width x height; zero outside the charts
  // Per finest-level triangle, two per texel (quad (i, j) .. (i + 1, j + 1) of its chart, its
  // triangles in squareTriangles' order; at 2 * texel + t): the normal of the dense face under the
  // triangle's centroid in the chart, the surface's own facing there (`normals` interpolate its vertex
  // normals for shading, and point against a small face beside large ones at a sharp crease; a
  // texel on a dense edge has no one face). Zero at each chart's last row and column and outside
  // the charts. Only in an atlas makeAtlas made: a model file does not keep them (empty).
  std::vector<Normal16> triangleFaceNormals;
  std::vector<DetailChart> details;             // by tile, each tile at most once; all of one size

  Vec3 position(std::uint32_t c, std::uint32_t i, std::uint32_t j) const {
    const auto& p = positions[layout.texel(c, i, j)];
    return {p[0], p[1], p[2]};
  }
  Vec3 normal(std::uint32_t c, std::uint32_t i, std::uint32_t j) const { return unpackNormal(normals[layout.texel(c, i, j)]); }
  Vec3 triangleFaceNormal(std::uint32_t c, std::uint32_t a, std::uint32_t b, int t) const {
    return unpackNormal(triangleFaceNormals[2 * layout.texel(c, a, b) + std::size_t(t)]);
  }
};

// The fullest grid of slots for `charts` charts whose width and height differ by at most a factor
// of 2 (ties: the squarer one). Throws Error(BadInput) for no charts.
AtlasLayout packCharts(std::uint32_t charts, std::uint32_t chartSize);

}  // namespace isoatlas::atlas
