// Texels moved where fewer of the finest level's triangles fold, against what
// unturnTexels promises, on a surface whose bumps are about a texel wide (the grid's chords across
// them face backwards), its texels placed off the uniform grid as relaxation leaves them: fewer such
// triangles after, some of the coarser levels' texels (i and j even) moved too; the grid strictly
// convex, its border where it was; no triangle or edge strays farther from the surface than the
// farthest before, and no dense vertex lies farther from the level than the farthest before (both
// measured here over the whole grid, not around the moved texels as unturnTexels does); a flat surface
// moves nothing.
#include <gtest/gtest.h>

#include <cmath>

#include "atlas/chart_grid.h"
#include "atlas/reconstruct.h"
#include "atlas/relax_chart.h"
#include "atlas/unturn_texels.h"

namespace isoatlas::atlas {
namespace {

using multires::Vec2;

// A height field over the chart and its unit normal.
SurfacePoint bumps(const Vec2& x, double amplitude, double waves) {
  const double k = 2 * M_PI * waves, z = amplitude * std::sin(k * x.x) * std::sin(k * x.y);
  const double dx = amplitude * k * std::cos(k * x.x) * std::sin(k * x.y), dy = amplitude * k * std::sin(k * x.x) * std::cos(k * x.y);
  const Vec3 n{-dx, -dy, 1};
  return {{x.x, x.y, z}, n * (1 / norm(n))};
}

// The finest level's triangles that fold: facing against the surface's normal under their centroid
// in the chart (countFoldedQuads' test).
int backFacing(std::uint32_t n, const std::vector<Vec2>& q, const std::function<SurfacePoint(const Vec2&)>& surface) {
  int turned = 0;
  for (std::uint32_t b = 0; b + 1 < n; ++b)
    for (std::uint32_t a = 0; a + 1 < n; ++a) {
      const std::size_t k = std::size_t(b) * n + a;
      const std::array<std::size_t, 4> corner{k, k + 1, k + n + 1, k + n};
      for (const auto& t : squareTriangles(a, b)) {
        const Vec2 &x = q[corner[std::size_t(t[0])]], &y = q[corner[std::size_t(t[1])]], &z = q[corner[std::size_t(t[2])]];
        const Vec3 u = surface(x).position, v = surface(y).position, w = surface(z).position;
        turned += dot(cross(v - u, w - u), surface((x + y + z) * (1.0 / 3)).normal) < 0;
      }
    }
  return turned;
}

struct Chart {
  std::vector<Vec2> q;
  std::vector<Vec3> p;
};
// The tile's uniform grid, the texels off the border moved by up to `jitter` of a spacing (a fixed
// pseudo-random pattern), as relaxation leaves them.
Chart uniformChart(std::uint32_t n, const std::function<SurfacePoint(const Vec2&)>& surface, double jitter = 0) {
  Chart c;
  for (std::uint32_t j = 0; j < n; ++j)
    for (std::uint32_t i = 0; i < n; ++i) {
      const bool inside = i > 0 && j > 0 && i + 1 < n && j + 1 < n;
      const double a = std::sin(12.9898 * i + 78.233 * j) * 43758.5453, b = std::sin(39.3468 * i + 11.135 * j) * 24634.6345;
      const double dx = inside ? jitter * (2 * (a - std::floor(a)) - 1) : 0, dy = inside ? jitter * (2 * (b - std::floor(b)) - 1) : 0;
      c.q.push_back({(i + dx) / (n - 1), (j + dy) / (n - 1)});
    }
  for (const Vec2& x : c.q) c.p.push_back(surface(x).position);
  return c;
}

TEST(UnturnTexels, TexelsMoveWhereFewerTrianglesFaceBackwardsAndNothingGetsFarther) {
  constexpr std::uint32_t n = 17;
  const auto surface = [](const Vec2& x) { return bumps(x, 0.1, 6.3); };
  const auto position = [&](const Vec2& x) { return surface(x).position; };
  std::vector<ChartVertex> vertices;  // dense vertices between the texels
  for (int j = 0; j < 23; ++j)
    for (int i = 0; i < 23; ++i) {
      const Vec2 x{(i + 0.5) / 23, (j + 0.5) / 23};
      vertices.push_back({x, position(x)});
    }
  Chart chart = uniformChart(n, surface, 0.3);
  for (std::uint32_t j = 0; j + 1 < n; ++j)
    for (std::uint32_t i = 0; i + 1 < n; ++i) ASSERT_TRUE(convexChartQuad(chart.q, n, i, j));
  const Chart before = chart;
  const int turnedBefore = backFacing(n, chart.q, surface);
  ASSERT_GT(turnedBefore, 0) << "the bumps must turn some of the uniform grid's triangles";
  const double strayBefore = ChartGrid(n, before.q, before.p).largestStray(position);
  const double vertexBefore = largestVertexError(ChartGrid(n, before.q, before.p), vertices);

  const std::uint32_t moved = unturnTexels(n, vertices, surface, chart.q, chart.p);
  EXPECT_GT(moved, 0u);
  EXPECT_LT(backFacing(n, chart.q, surface), turnedBefore);
  for (std::uint32_t j = 0; j + 1 < n; ++j)
    for (std::uint32_t i = 0; i + 1 < n; ++i) EXPECT_TRUE(convexChartQuad(chart.q, n, i, j)) << "square " << i << ", " << j;
  int coarserMoved = 0;
  for (std::uint32_t j = 0; j < n; ++j)
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::size_t k = std::size_t(j) * n + i;
      const bool border = i == 0 || j == 0 || i + 1 == n || j + 1 == n;
      coarserMoved += !border && i % 2 == 0 && j % 2 == 0 && (chart.q[k].x != before.q[k].x || chart.q[k].y != before.q[k].y);
      if (border) {
        EXPECT_EQ(chart.q[k].x, before.q[k].x) << i << ", " << j;
        EXPECT_EQ(chart.q[k].y, before.q[k].y) << i << ", " << j;
      }
      const Vec3 expected = position(chart.q[k]);
      EXPECT_TRUE(chart.p[k].x == expected.x && chart.p[k].y == expected.y && chart.p[k].z == expected.z) << "texel " << i << ", " << j << ": not the surface at its chart point";
    }
  EXPECT_GT(coarserMoved, 0) << "only the finest two levels' texels moved";
  EXPECT_LE(ChartGrid(n, chart.q, chart.p).largestStray(position), strayBefore * (1 + 1e-12));
  EXPECT_LE(largestVertexError(ChartGrid(n, chart.q, chart.p), vertices), vertexBefore * (1 + 1e-12));
}

TEST(UnturnTexels, AFlatSurfaceMovesNothing) {
  constexpr std::uint32_t n = 9;
  const auto surface = [](const Vec2& x) { return bumps(x, 0, 1); };
  Chart chart = uniformChart(n, surface);
  EXPECT_EQ(unturnTexels(n, {}, surface, chart.q, chart.p), 0u);
}

}  // namespace
}  // namespace isoatlas::atlas
