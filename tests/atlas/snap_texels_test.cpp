// Texels drawn onto the dense vertices the grid misses, against what snapTexels promises: a spike
// between texels gets a texel on its tip; the grid stays strictly convex, its border and coarser
// texels where they were; a move that would fold the grid is refused; on a bumpy surface no
// vertex's distance from the finest level ends above the largest before (measured here by brute-force
// location in the level's triangles, not by the walk snapTexels uses); a flat surface moves nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "atlas/reconstruct.h"
#include "atlas/relax_chart.h"
#include "atlas/snap_texels.h"
#include "multires/exact_orientation.h"

namespace isoatlas::atlas {
namespace {

using multires::Vec2;

std::vector<Vec2> uniformGrid(std::uint32_t n) {
  std::vector<Vec2> q;
  for (std::uint32_t j = 0; j < n; ++j)
    for (std::uint32_t i = 0; i < n; ++i) q.push_back({double(i) / (n - 1), double(j) / (n - 1)});
  return q;
}

std::vector<Vec3> sampled(const std::vector<Vec2>& q, const std::function<Vec3(const Vec2&)>& surface) {
  std::vector<Vec3> p;
  for (const Vec2& x : q) p.push_back(surface(x));
  return p;
}

// The finest level's point at chart point x: the triangle of the grid (cut as reconstructLevel cuts
// it) that holds x, found by trying them all.
Vec3 levelPoint(std::uint32_t n, const std::vector<Vec2>& q, const std::vector<Vec3>& p, const Vec2& x) {
  for (std::uint32_t b = 0; b + 1 < n; ++b)
    for (std::uint32_t a = 0; a + 1 < n; ++a) {
      const std::size_t k = std::size_t(b) * n + a;
      const std::size_t c[4] = {k, k + 1, k + n + 1, k + n};
      for (const auto& h : squareTriangles(a, b)) {
        const std::size_t u = c[h[0]], v = c[h[1]], w = c[h[2]];
        if (!multires::exactlyInTriangle(x, q[u], q[v], q[w])) continue;
        const auto bary = multires::barycentric2(x, q[u], q[v], q[w]);
        return p[u] * bary[0] + p[v] * bary[1] + p[w] * bary[2];
      }
    }
  ADD_FAILURE() << "no triangle holds " << x.x << ", " << x.y;
  return {};
}

void expectStrictlyConvex(std::uint32_t n, const std::vector<Vec2>& q) {
  for (std::uint32_t j = 0; j + 1 < n; ++j)
    for (std::uint32_t i = 0; i + 1 < n; ++i) EXPECT_TRUE(convexChartQuad(q, n, i, j)) << "square " << i << ", " << j;
}

TEST(SnapTexels, ASpikeBetweenTexelsGetsATexelOnItsTip) {
  constexpr std::uint32_t n = 9;
  const Vec2 tip{0.52, 0.44};
  auto surface = [&](const Vec2& x) {
    const double r = std::hypot(x.x - tip.x, x.y - tip.y);
    return Vec3{x.x, x.y, 0.3 * std::max(0.0, 1 - r / 0.04)};
  };
  std::vector<Vec2> q = uniformGrid(n);
  std::vector<Vec3> p = sampled(q, surface);
  const std::vector<Vec2> before = q;
  const std::vector<ChartVertex> vertices{{tip, surface(tip)}, {{0.2, 0.7}, surface({0.2, 0.7})}};
  EXPECT_NEAR(norm(levelPoint(n, q, p, tip) - vertices[0].position), 0.3, 1e-12) << "the grid misses the spike";

  EXPECT_EQ(snapTexels(n, vertices, surface, q, p), 1u);
  const auto onTip = std::find_if(q.begin(), q.end(), [&](const Vec2& x) { return x.x == tip.x && x.y == tip.y; });
  ASSERT_NE(onTip, q.end());
  const std::size_t k = std::size_t(onTip - q.begin());
  EXPECT_TRUE(k % n % 2 == 1 || k / n % 2 == 1) << "a texel of the finest two levels moved";
  EXPECT_EQ(norm(p[k] - vertices[0].position), 0.0);
  EXPECT_LT(norm(levelPoint(n, q, p, tip) - vertices[0].position), 1e-12);
  expectStrictlyConvex(n, q);
  for (std::uint32_t j = 0; j < n; ++j)
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::size_t m = std::size_t(j) * n + i;
      if (m == k) continue;
      {
      EXPECT_EQ(q[m].x, before[m].x);
      EXPECT_EQ(q[m].y, before[m].y);
    }
      EXPECT_EQ(norm(p[m] - surface(q[m])), 0.0);
    }
}

TEST(SnapTexels, AMoveThatWouldFoldTheGridIsRefused) {
  // The square at the chart's corner (0, 0): its one movable corner, texel (1, 1), taken to the
  // spike would turn the square's corner there clockwise.
  constexpr std::uint32_t n = 5;
  const Vec2 tip{0.01, 0.2};
  auto surface = [&](const Vec2& x) { return Vec3{x.x, x.y, std::hypot(x.x - tip.x, x.y - tip.y) < 0.02 ? 0.5 : 0.0}; };
  std::vector<Vec2> q = uniformGrid(n);
  std::vector<Vec3> p = sampled(q, surface);
  const std::vector<Vec2> before = q;
  const std::vector<ChartVertex> vertices{{tip, surface(tip)}};
  EXPECT_EQ(snapTexels(n, vertices, surface, q, p), 0u);
  for (std::size_t m = 0; m < q.size(); ++m) {
      EXPECT_EQ(q[m].x, before[m].x);
      EXPECT_EQ(q[m].y, before[m].y);
    }
}

TEST(SnapTexels, NoVertexEndsFartherThanTheFarthestBefore) {
  constexpr std::uint32_t n = 17;
  auto surface = [](const Vec2& x) {
    return Vec3{x.x, x.y, 0.05 * std::sin(40 * x.x) * std::cos(33 * x.y) + 0.02 * std::sin(90 * x.x * x.y)};
  };
  std::vector<Vec2> q = uniformGrid(n);
  std::vector<Vec3> p = sampled(q, surface);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> inside(0.001, 0.999);
  std::vector<ChartVertex> vertices;
  for (int m = 0; m < 600; ++m) {
    const Vec2 x{inside(random), inside(random)};
    vertices.push_back({x, surface(x)});
  }
  auto errors = [&] {
    std::vector<double> e;
    for (const ChartVertex& v : vertices) e.push_back(norm(levelPoint(n, q, p, v.chart) - v.position));
    return e;
  };
  const std::vector<double> before = errors();
  const std::uint32_t snapped = snapTexels(n, vertices, surface, q, p);
  const std::vector<double> after = errors();
  EXPECT_GT(snapped, 20u);
  const double largestBefore = *std::max_element(before.begin(), before.end());
  EXPECT_LE(*std::max_element(after.begin(), after.end()), largestBefore);
  double sumBefore = 0, sumAfter = 0;
  for (std::size_t m = 0; m < before.size(); ++m) sumBefore += before[m], sumAfter += after[m];
  EXPECT_LT(sumAfter, sumBefore);
  expectStrictlyConvex(n, q);
  const std::vector<Vec2> grid = uniformGrid(n);
  for (std::size_t k = 0; k < q.size(); ++k) {
    const std::size_t i = k % n, j = k / n;
    const bool border = i == 0 || j == 0 || i == n - 1 || j == n - 1, coarser = i % 2 == 0 && j % 2 == 0;
    if (border || coarser) {
      EXPECT_EQ(q[k].x, grid[k].x) << "texel " << i << ", " << j;
      EXPECT_EQ(q[k].y, grid[k].y) << "texel " << i << ", " << j;
    }
  }
}

TEST(SnapTexels, AFlatSurfaceMovesNothing) {
  constexpr std::uint32_t n = 9;
  auto plane = [](const Vec2& x) { return Vec3{2 * x.x, x.y, 0.5 * x.x + 0.25 * x.y}; };
  std::vector<Vec2> q = uniformGrid(n);
  std::vector<Vec3> p = sampled(q, plane);
  std::vector<ChartVertex> vertices;
  for (int m = 1; m < 50; ++m) {
    const Vec2 x{std::fmod(m * 0.618, 1.0), std::fmod(m * 0.414, 1.0)};
    vertices.push_back({x, plane(x)});
  }
  EXPECT_EQ(snapTexels(n, vertices, plane, q, p), 0u);
}

}  // namespace
}  // namespace isoatlas::atlas
