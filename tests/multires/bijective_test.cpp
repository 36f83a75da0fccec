// The parametrisation is one-to-one by construction: exact orientation and point location against
// brute force, welds whose fan would fold refused by planWeld, and the history that maps base points
// back to the dense mesh as the inverse of the forward map.
#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "multires/exact_orientation.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"
#include "multires/weld_plan.h"
#include "tests/multires/mesh_shapes.h"

namespace isoatlas::multires {
namespace {

TEST(ExactOrientation, TheFilterAnswersAsTheExactTest) {
  // Near-collinear triples, where the floating-point determinant is at the mercy of rounding, and
  // exactly collinear ones (dyadic steps along a segment between lattice points).
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(-1, 1);
  int zeros = 0;
  for (int i = 0; i < 20000; ++i) {
    // Lattice ends and a dyadic step keep c exactly on the line through a and b (odd i); else a
    // random step, rounded off it.
    const Vec2 a{std::round(unit(random) * 100), std::round(unit(random) * 100)};
    const Vec2 b{std::round(unit(random) * 100), std::round(unit(random) * 100)};
    const double s = i % 2 ? std::ldexp(double(i % 64), -6) : unit(random);
    Vec2 c = a + (b - a) * s;
    if (i % 3 == 0) c.x = std::nextafter(c.x, i % 6 ? 1e9 : -1e9);
    const int slow = exactOrientationSlow(a, b, c);
    ASSERT_EQ(exactOrientation(a, b, c), slow) << i;
    zeros += slow == 0;
  }
  EXPECT_GT(zeros, 1000) << "the test must reach the exactly collinear case";
}

bool strictlyHeld(const Vec2& p, const std::array<Vec2, 3>& c) {
  return exactOrientationSlow(c[0], c[1], p) > 0 && exactOrientationSlow(c[1], c[2], p) > 0 && exactOrientationSlow(c[2], c[0], p) > 0;
}

// A fan of triangles over a convex polygon on a lattice, and points on the lattice and on its
// edges: locateExactly finds a triangle that holds the point by the exact test, and finds one
// exactly when brute force (every triangle, exact test) does.
TEST(ExactLocation, AgreesWithBruteForce) {
  const std::vector<Vec2> polygon{{0, 0}, {8, -2}, {12, 3}, {10, 9}, {3, 11}, {-3, 6}};
  const Vec2 apex{4, 3};
  auto corners = [&](std::size_t t) {
    return std::array<Vec2, 3>{apex, polygon[t], polygon[(t + 1) % polygon.size()]};
  };
  int inside = 0, onEdges = 0;
  for (int y = -8; y <= 26; ++y)
    for (int x = -8; x <= 26; ++x)
      for (const double scale : {1.0, 0.5}) {
        const Vec2 p{x * scale, y * scale};
        std::vector<std::size_t> holding;
        for (std::size_t t = 0; t < polygon.size(); ++t) {
          const auto c = corners(t);
          if (exactOrientationSlow(c[0], c[1], p) >= 0 && exactOrientationSlow(c[1], c[2], p) >= 0 &&
              exactOrientationSlow(c[2], c[0], p) >= 0)
            holding.push_back(t);
        }
        // A walk from any triangle ends strictly inside one, held by that triangle alone; the fan's
        // polygon is convex, so a point strictly inside a triangle is always reached.
        const std::size_t k = polygon.size();
        auto across = [&](std::size_t t, int side) { return side == 0 ? kNoTriangleHit : side == 1 ? (t + 1) % k : (t + k - 1) % k; };
        for (std::size_t from = 0; from < k; ++from) {
          const TriangleHit strict = walkStrictlyInside(p, from, k, corners, across);
          if (strict.triangle == kNoTriangleHit) {
            EXPECT_FALSE(holding.size() == 1 && strictlyHeld(p, corners(holding[0]))) << p.x << ", " << p.y << " from " << from;
            continue;
          }
          ASSERT_EQ(holding, std::vector<std::size_t>{strict.triangle}) << p.x << ", " << p.y;
          EXPECT_EQ(strict.bary, locateExactly(p, k, corners).bary);
        }
        for (std::size_t hint = 0; hint < polygon.size(); hint += 2) {
          const TriangleHit hit = locateExactly(p, polygon.size(), corners, hint);
          if (holding.empty()) {
            ASSERT_EQ(hit.triangle, kNoTriangleHit) << p.x << ", " << p.y;
            continue;
          }
          ASSERT_NE(std::find(holding.begin(), holding.end(), hit.triangle), holding.end()) << p.x << ", " << p.y;
          const auto c = corners(hit.triangle);
          const Vec2 back = c[0] * hit.bary[0] + c[1] * hit.bary[1] + c[2] * hit.bary[2];
          EXPECT_NEAR(back.x, p.x, 1e-12);
          EXPECT_NEAR(back.y, p.y, 1e-12);
        }
        inside += !holding.empty();
        onEdges += holding.size() > 1;
      }
  EXPECT_GT(inside, 300);
  EXPECT_GT(onEdges, 10) << "points on the spokes must be among those tested";
}

// A triangle thin enough that its floating-point area rounds to zero, though it is exactly positive:
// a point inside gets its own weights (barycentric2 alone gives the centroid's thirds there).
TEST(ExactLocation, WeightsInATriangleWhoseAreaRoundsToZero) {
  // A sliver along the diagonal, its apex c a hair above the origin: c - a rounds to (1, 1).
  const double height = 1e-20;
  const Vec2 a{-1, -1}, b{1, 1}, c{0, height}, p{0, height / 4};
  ASSERT_EQ(orient2(a, b, c), 0.0);
  ASSERT_GT(exactOrientationSlow(a, b, c), 0);
  ASSERT_TRUE(exactOrientationSlow(a, b, p) > 0 && exactOrientationSlow(b, c, p) > 0 && exactOrientationSlow(c, a, p) > 0);
  const auto corners = [&](std::size_t) { return std::array<Vec2, 3>{a, b, c}; };
  const TriangleHit hit = locateExactly(p, 1, corners);
  ASSERT_EQ(hit.triangle, 0u);
  // By hand: p's weight at c is its height over c's (a quarter); a and b share the rest.
  EXPECT_NEAR(hit.bary[0], 0.375, 1e-12);
  EXPECT_NEAR(hit.bary[1], 0.375, 1e-12);
  EXPECT_NEAR(hit.bary[2], 0.25, 1e-12);
}

// A ring laid flat: k vertices at the given radii, evenly around the origin.
std::vector<Vec2> ring(const std::vector<double>& radii) {
  std::vector<Vec2> plane;
  for (std::size_t i = 0; i < radii.size(); ++i) {
    const double a = 2 * std::numbers::pi * double(i) / double(radii.size());
    plane.push_back({radii[i] * std::cos(a), radii[i] * std::sin(a)});
  }
  return plane;
}

// The fan a weld into t leaves, judged directly: every triangle (u, w_j, w_j+1) counter-clockwise.
bool fanIsValid(const std::vector<Vec2>& plane, std::size_t t) {
  const std::size_t k = plane.size();
  for (std::size_t j = 1; j + 1 < k; ++j)
    if (orient2(plane[t], plane[(t + j) % k], plane[(t + j + 1) % k]) <= 0) return false;
  return true;
}

TEST(WeldPlan, ConvexRingsWeldIntoAnyNeighbour) {
  for (std::size_t k = 3; k <= 12; ++k) {
    const std::vector<Vec2> plane = ring(std::vector<double>(k, 1.0));
    ASSERT_TRUE(starIsValid(plane, false));
    for (std::size_t t = 0; t < k; ++t) {
      WeldPlan plan;
      ASSERT_TRUE(planWeld(plane, false, t, plan)) << "k " << k << ", t " << t;
      EXPECT_EQ(plan.flipCount, k > 4 ? k - 4 : 0);
      EXPECT_EQ(plan.rimSize, k - 1);
    }
  }
}

TEST(WeldPlan, AWeldWhoseFanWouldFoldIsRefused) {
  // A star: spikes at radius 1, notches at radius 0.3. From a spike the fan crosses the notches
  // beside it (clockwise triangles): refused. From a notch it may be sound; planWeld accepts
  // exactly when the fan is valid and its flips are convex, so never a folding fan.
  const std::vector<Vec2> plane = ring({1, 0.3, 1, 0.3, 1, 0.3, 1, 0.3, 1, 0.3});
  ASSERT_TRUE(starIsValid(plane, false));
  int refused = 0;
  for (std::size_t t = 0; t < plane.size(); ++t) {
    WeldPlan plan;
    const bool ok = planWeld(plane, false, t, plan);
    if (!fanIsValid(plane, t)) {
      EXPECT_FALSE(ok) << "t " << t;
    }
    refused += !ok;
    if (t % 2 == 0) {
      EXPECT_FALSE(ok) << "a spike sees no notch across the star";
    }
  }
  EXPECT_GE(refused, 5);
  // Four neighbours, one of them reflex (w_2): no flips, and welding into w_1 leaves the fan
  // (w_1, w_2, w_3) clockwise; into w_0 it stays sound.
  const std::vector<Vec2> quad{{1, 0}, {-0.5, 0.87}, {-0.2, 0}, {-0.5, -0.87}};
  ASSERT_TRUE(starIsValid(quad, false));
  WeldPlan plan;
  EXPECT_TRUE(planWeld(quad, false, 0, plan));
  EXPECT_FALSE(fanIsValid(quad, 1));
  EXPECT_FALSE(planWeld(quad, false, 1, plan));
  // A star that is folded already (a ring vertex past its neighbour) is no valid layout at all.
  std::vector<Vec2> folded = ring(std::vector<double>(6, 1.0));
  std::swap(folded[1], folded[2]);
  EXPECT_FALSE(starIsValid(folded, false));
}

TEST(WeldPlan, BoundaryWeldsFlipAlongTheOpenRing) {
  // A boundary vertex's ring over a half turn: welds into either end, k - 3 flips, a fan of k - 2.
  std::vector<Vec2> plane;
  const std::size_t k = 7;
  for (std::size_t i = 0; i < k; ++i) {
    const double a = std::numbers::pi * double(i) / double(k - 1);
    plane.push_back({std::cos(a), std::sin(a)});
  }
  ASSERT_TRUE(starIsValid(plane, true));
  for (const std::size_t t : {std::size_t(0), k - 1}) {
    WeldPlan plan;
    ASSERT_TRUE(planWeld(plane, true, t, plan));
    EXPECT_EQ(plan.flipCount, k - 3);
    EXPECT_EQ(plan.rimSize, k - 1);
  }
}

// The history maps back what the forward map sent: every dense vertex, sent to its base triangle and
// weights, comes back to itself (the two are inverse maps), before and after pairing splits edges.
void expectHistoryInvertsTheForwardMap(const Mesh& dense, double ratio) {
  SimplifyStats stats;
  BaseMesh base = simplifyStellar(dense, {.vertexRatio = ratio}, &stats);
  EXPECT_EQ(stats.historySteps, dense.vertexCount() - base.vertexCount());
  const double size = boundingBox(dense.positions).diagonal();
  for (const bool paired : {false, true}) {
    if (paired) pairTriangles(base, dense);
    double worst = 0;
    ParametrisationHistory::Hints hints;
    auto expectSameWithHints = [&](std::uint32_t triangle, const ParametrisationHistory::Bary& bary) {
      const ParametrisationHistory::DensePoint p = base.densePoint(triangle, bary), hinted = base.densePoint(triangle, bary, &hints);
      EXPECT_TRUE(p.face == hinted.face && p.bary == hinted.bary && p.outside == hinted.outside && p.steps == hinted.steps)
          << "triangle " << triangle;
      return p;
    };
    for (std::uint32_t d = 0; d < dense.vertexCount(); ++d) {
      const ParametrisationHistory::DensePoint p = expectSameWithHints(base.denseTriangle[d], base.denseBary[d]);
      EXPECT_LE(p.outside, ParametrisationHistory::kGapWeight);
      worst = std::max(worst, norm(densePosition(dense, p) - dense.positions[d]));
    }
    EXPECT_LT(worst, 1e-9 * size) << (paired ? "after pairing" : "before pairing");
    // Hints change nothing on the base triangles' sides and corners either, where points lie on
    // the edges of the faces they pass through.
    for (std::uint32_t t = 0; t < base.triangleCount(); ++t)
      for (const ParametrisationHistory::Bary& bary :
           {ParametrisationHistory::Bary{0.5, 0.5, 0}, {0, 0.25, 0.75}, {1, 0, 0}, {0.2, 0.3, 0.5}})
        expectSameWithHints(t, bary);
  }
}

TEST(ParametrisationHistory, InvertsTheForwardMap) {
  expectHistoryInvertsTheForwardMap(test::torusMesh(60, 30), 0.02);
  expectHistoryInvertsTheForwardMap(test::doubleTorusMesh(), 0.02);
  expectHistoryInvertsTheForwardMap(test::gridMesh(30, 20, [](int i, int j) { return i >= 5 && i < 9 && j >= 5 && j < 9; }), 0.03);
}

// A point on an edge that a step kept keeps its weights there, whatever the faces look like in the
// step's layout: here the face it replaced is so thin that its area rounds to zero (its exact
// orientation is still positive), where placing the point and locating it again would give the
// edge's midpoint. Both sides of a base edge then reach the same dense point (the atlas's borders).
TEST(ParametrisationHistory, APointOnAKeptEdgeKeepsItsWeights) {
  ParametrisationHistory history(2);
  const Vec2 layout[] = {{0, 0}, {1e-200, 0}, {0, 1e-200}, {1e-200, 1e-200}};
  history.beginStep(layout);
  history.replaces(0, {0, 1, 2});
  history.replaces(1, {1, 3, 2});
  const std::uint32_t lower = history.adds({0, 1, 3}), upper = history.adds({0, 3, 2});
  const ParametrisationHistory::DensePoint onBottom = history.toDense(lower, {0.75, 0.25, 0});
  EXPECT_EQ(onBottom.face, 0u);
  EXPECT_EQ(onBottom.bary, (ParametrisationHistory::Bary{0.75, 0.25, 0}));
  const ParametrisationHistory::DensePoint onLeft = history.toDense(upper, {0.375, 0, 0.625});
  EXPECT_EQ(onLeft.face, 0u);
  EXPECT_EQ(onLeft.bary, (ParametrisationHistory::Bary{0.375, 0, 0.625}));
  const ParametrisationHistory::DensePoint onRight = history.toDense(lower, {0, 0.125, 0.875});
  EXPECT_EQ(onRight.face, 1u);
  EXPECT_EQ(onRight.bary, (ParametrisationHistory::Bary{0.125, 0.875, 0}));
}

}  // namespace
}  // namespace isoatlas::multires
