// Texels placed over their tile against what the placement promises: a flat, evenly mapped tile
// keeps its uniform grid; a side's fractions rise from 0 to 1, keep the coarse lattice, read the
// same from both ends, and gather at a crease; a chart's grid stays strictly convex with its border
// where the sides put it, evens out a stretched map and gathers at a crease; level 2's centre leaves
// a spike that would tent it over a bowl; and on a model with creases the finest level lies closer
// to the dense surface than the uniform grid's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "core/distance/mesh_distance.h"
#include "atlas/make_atlas.h"
#include "atlas/reconstruct.h"
#include "atlas/relax_chart.h"
#include "atlas/tile_sides.h"
#include "multires/exact_orientation.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"

namespace isoatlas::atlas {
namespace {

using multires::Vec2;
constexpr std::uint32_t kN = 33;
const ChartRelaxing kHow{.sweeps = 8, .flatCurvature = 0.1, .keptSize = 3};

// A ridge along u = 0.3 (a crease of 90 degrees), its normals those of the two flanks.
SurfacePoint ridge(const Vec2& q) {
  const double side = q.x < 0.3 ? -1 : 1;
  return {{q.x, q.y, -std::abs(q.x - 0.3)}, Vec3{side, 0, 1} * (1 / std::sqrt(2.0))};
}

std::array<std::vector<double>, 4> uniformSides() {
  std::vector<double> t(kN);
  for (std::uint32_t m = 0; m < kN; ++m) t[m] = double(m) / (kN - 1);
  return {t, t, t, t};
}

TEST(RelaxChart, AFlatEvenMapKeepsTheUniformGrid) {
  auto flat = [](const Vec2& q) { return SurfacePoint{{2 * q.x, 2 * q.y, 0}, {0, 0, 1}}; };
  const auto side = relaxSide(kN, [&](double t) { return flat({t, 0}); }, kHow);
  const auto q = relaxChart(kN, flat, {side, side, side, side}, kHow);
  for (std::uint32_t j = 0; j < kN; ++j)
    for (std::uint32_t i = 0; i < kN; ++i) {
      EXPECT_NEAR(q[j * kN + i].x, double(i) / (kN - 1), 1e-9);
      EXPECT_NEAR(q[j * kN + i].y, double(j) / (kN - 1), 1e-9);
    }
}

TEST(RelaxChart, SideFractionsRiseKeepTheLatticeReadBothWaysAndGatherAtACrease) {
  const auto t = relaxSide(kN, [](double f) { return ridge({f, 0.5}); }, kHow);
  ASSERT_EQ(t.size(), kN);
  EXPECT_EQ(t.front(), 0.0);
  EXPECT_EQ(t.back(), 1.0);
  for (std::uint32_t m = 1; m < kN; ++m) EXPECT_LT(t[m - 1], t[m]);
  const std::uint32_t kept = (kN - 1) / (kHow.keptSize - 1);
  for (std::uint32_t m = 0; m < kN; m += kept) EXPECT_EQ(t[m], double(m) / (kN - 1)) << "the kept lattice stays";
  for (const double f : t) {
    const double steps = std::ldexp(f, 32);  // on the grid of 2^-32, so 1 - f is exact too
    EXPECT_EQ(steps, std::floor(steps)) << f;
  }
  // The spacing at the crease (between the kept texels around 0.3) against the spacing away from it
  // in the same interval.
  double atCrease = 1, away = 0;
  for (std::uint32_t m = 0; m < kept; ++m) {
    const double spacing = t[m + 1] - t[m];
    if (t[m] <= 0.3 && t[m + 1] >= 0.3) atCrease = spacing;
    else away = std::max(away, spacing);
  }
  EXPECT_LT(atCrease, away / 2);
}

// Per quad of the grid, whether it is strictly convex and counter-clockwise.
std::size_t nonConvexQuads(const std::vector<Vec2>& q) {
  std::size_t bad = 0;
  for (std::uint32_t j = 0; j + 1 < kN; ++j)
    for (std::uint32_t i = 0; i + 1 < kN; ++i) {
      const std::size_t k = j * kN + i;
      const Vec2 c[4] = {q[k], q[k + 1], q[k + kN + 1], q[k + kN]};
      for (int m = 0; m < 4; ++m) bad += multires::exactOrientation(c[m], c[(m + 1) % 4], c[(m + 2) % 4]) <= 0;
    }
  return bad;
}

TEST(RelaxChart, AStretchedMapIsEvenedOutWithinConvexQuads) {
  // u is squeezed near 0 and stretched near 1 on the surface.
  auto stretched = [](const Vec2& q) { return SurfacePoint{{q.x * q.x * 4, q.y, 0}, {0, 0, 1}}; };
  const auto sides = uniformSides();
  std::uint32_t nonConvex = 99;
  const auto q = relaxChart(kN, stretched, sides, kHow, &nonConvex);
  EXPECT_EQ(nonConvex, 0u);
  EXPECT_EQ(nonConvexQuads(q), 0u);
  for (std::uint32_t m = 0; m < kN; ++m) {  // the border where the sides put it
    EXPECT_EQ(q[m].x, sides[0][m]);
    EXPECT_EQ(q[m].y, 0.0);
    EXPECT_EQ(q[(kN - 1) * kN + m].y, 1.0);
    EXPECT_EQ(q[m * kN].x, 0.0);
    EXPECT_EQ(q[m * kN + kN - 1].x, 1.0);
  }
  // Along the middle row, between the kept texels 24 and 32: the surface spacings even out.
  auto spread = [&](const std::vector<Vec2>& grid) {
    double lo = 1e9, hi = 0;
    for (std::uint32_t i = 24; i < 32; ++i) {
      const double s = norm(stretched(grid[16 * kN + i + 1]).position - stretched(grid[16 * kN + i]).position);
      lo = std::min(lo, s), hi = std::max(hi, s);
    }
    return hi / lo;
  };
  const auto uniform = relaxChart(kN, stretched, sides, {.sweeps = 0});
  EXPECT_LT(spread(q), 1 + (spread(uniform) - 1) / 2);
}

TEST(RelaxChart, TexelsGatherAtACrease) {
  const auto side = relaxSide(kN, [](double t) { return ridge({t, 0}); }, kHow);
  const auto top = relaxSide(kN, [](double t) { return ridge({1 - t, 1}); }, kHow);
  const auto q = relaxChart(kN, ridge, {side, uniformSides()[1], top, uniformSides()[3]}, kHow);
  EXPECT_EQ(nonConvexQuads(q), 0u);
  // On the middle row, the texel spacing across the crease is well below the row's widest.
  double atCrease = 1, widest = 0;
  for (std::uint32_t i = 0; i + 1 < kN; ++i) {
    const double spacing = q[16 * kN + i + 1].x - q[16 * kN + i].x;
    if (q[16 * kN + i].x <= 0.3 && q[16 * kN + i + 1].x >= 0.3) atCrease = spacing;
    widest = std::max(widest, spacing);
  }
  EXPECT_LT(atCrease, widest / 2);
}

// A crease cutting off a corner: the sides move their texels near the corner towards the crease,
// and the grid relaxed between them stays strictly convex.
TEST(RelaxChart, ACreaseAcrossACornerKeepsEveryQuadConvex) {
  auto cornerRidge = [](const Vec2& q) {
    const double d = (q.x + q.y - 0.2) / std::sqrt(2.0);
    const Vec3 flank = d < 0 ? Vec3{-0.5, -0.5, 1} : Vec3{0.5, 0.5, 1};
    return SurfacePoint{{q.x, q.y, -1.5 * std::abs(d)}, flank * (1 / norm(flank))};
  };
  std::array<std::vector<double>, 4> sides;
  for (int s = 0; s < 4; ++s) sides[s] = relaxSide(kN, [&](double t) { return cornerRidge(sidePoint(s, t)); }, kHow);
  for (const int s : {0, 3}) {  // the crease crosses sides 0 and 3 at 0.2 from the corner
    const auto& t = sides[std::size_t(s)];
    const double at = s == 0 ? 0.2 : 0.8;
    const auto m = std::size_t(std::upper_bound(t.begin(), t.end(), at) - t.begin());
    ASSERT_LT(t[m] - t[m - 1], 0.5 / (kN - 1)) << "side " << s << " gathers its texels at the crease";
    const double nearCorner = s == 0 ? t[1] : 1 - t[kN - 2];  // the texel next to the corner (0, 0)
    ASSERT_GT(nearCorner, 1.0 / (kN - 1)) << "side " << s << " moves its texels away from the corner";
  }
  std::uint32_t nonConvex = 99;
  const auto q = relaxChart(kN, cornerRidge, sides, kHow, &nonConvex);
  EXPECT_EQ(nonConvex, 0u);
  EXPECT_EQ(nonConvexQuads(q), 0u);
}

// The reviewer's corner: a coarse grid of 3 whose centre moved towards the corner (0, 0), sides
// whose new texels moved away from it; the refined grid is still strictly convex.
TEST(RelaxChart, RefiningKeepsAConvexGridConvex) {
  std::vector<Vec2> coarse;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) coarse.push_back({i / 2.0, j / 2.0});
  coarse[4] = {0.3, 0.3};
  const std::vector<double> even{0, 0.25, 0.5, 0.75, 1};
  // Side 0's texel 1 at u = 0.45; side 3 (from (0, 1) down) puts texel (0, 1) at v = 1 - 0.55.
  const std::array<std::vector<double>, 4> sides{std::vector<double>{0, 0.45, 0.5, 0.75, 1}, even, even,
                                                 std::vector<double>{0, 0.25, 0.5, 0.55, 1}};
  const std::vector<Vec2> fine = refineChartGrid(3, coarse, sides);
  ASSERT_EQ(fine.size(), 25u);
  EXPECT_EQ(fine[1].x, 0.45);
  EXPECT_DOUBLE_EQ(fine[5].y, 0.45);
  EXPECT_EQ(fine[12].x, 0.3) << "the old texels stay";
  for (std::uint32_t j = 0; j + 1 < 5; ++j)
    for (std::uint32_t i = 0; i + 1 < 5; ++i) {
      const std::size_t k = j * 5 + i;
      const Vec2 c[4] = {fine[k], fine[k + 1], fine[k + 6], fine[k + 5]};
      for (int m = 0; m < 4; ++m)
        EXPECT_GT(multires::exactOrientation(c[m], c[(m + 1) % 4], c[(m + 2) % 4]), 0) << "quad " << i << ", " << j;
    }
}

// The grid of 5 a side spanned by the sides alone, refined by hand from the tile's corners.
std::vector<Vec2> spannedGridOfFive(const std::array<std::vector<double>, 4>& sides) {
  auto every = [&](std::uint32_t step) {
    std::array<std::vector<double>, 4> out;
    for (int s = 0; s < 4; ++s)
      for (std::uint32_t m = 0; m < kN; m += step) out[std::size_t(s)].push_back(sides[std::size_t(s)][m]);
    return out;
  };
  return refineChartGrid(3, refineChartGrid(2, {{0, 0}, {1, 0}, {0, 1}, {1, 1}}, every(16)), every(8));
}

// The coarsest grid relaxChart moves (5 a side) lies no farther from the surface, by levelError, than
// the same grid spanned by its sides alone: on some surfaces it keeps its relaxed places, on others
// it goes back to the spanned ones.
TEST(RelaxChart, TheCoarsestRelaxedGridIsNoFartherThanItsSidesSpan) {
  const std::vector<std::function<SurfacePoint(const Vec2&)>> surfaces{
      ridge,
      [](const Vec2& q) {  // a ridge across the tile's diagonal
        const double side = q.x - q.y < 0.1 ? -1 : 1;
        return SurfacePoint{{q.x, q.y, -std::abs(q.x - q.y - 0.1)}, Vec3{side, -side, 1} * (1 / std::sqrt(3.0))};
      },
      [](const Vec2& q) {  // a bump
        const double z = std::exp(-20 * ((q.x - 0.6) * (q.x - 0.6) + (q.y - 0.4) * (q.y - 0.4)));
        const Vec3 n{40 * (q.x - 0.6) * z, 40 * (q.y - 0.4) * z, 1};
        return SurfacePoint{{q.x, q.y, z}, n * (1 / norm(n))};
      },
      [](const Vec2& q) {  // a crease beside a side
        const double side = q.y < 0.1 ? -1 : 1;
        return SurfacePoint{{q.x, q.y, -0.5 * std::abs(q.y - 0.1)}, Vec3{0, 0.5 * side, 1} * (1 / std::sqrt(1.25))};
      }};
  const auto sides = uniformSides();
  const std::vector<Vec2> spanned = spannedGridOfFive(sides);
  int keptRelaxed = 0, wentBack = 0;
  for (const auto& surface : surfaces) {
    const auto q = relaxChart(kN, surface, sides, kHow);
    std::vector<Vec2> coarsest;
    for (std::uint32_t j = 0; j < kN; j += 8)
      for (std::uint32_t i = 0; i < kN; i += 8) coarsest.push_back(q[j * kN + i]);
    EXPECT_LE(levelError(5, coarsest, surface, {}), levelError(5, spanned, surface, {}));
    const bool same = std::equal(coarsest.begin(), coarsest.end(), spanned.begin(), [](const Vec2& a, const Vec2& b) { return a.x == b.x && a.y == b.y; });
    (same ? wentBack : keptRelaxed) += 1;
  }
  EXPECT_GT(keptRelaxed, 0);
  EXPECT_GT(wentBack, 0);
}

// coarsestRelaxedError (the judge of a side's fractions) measures the grid of 5 as its sides span
// it: with one side's fractions and the others uniform, levelError of that grid.
TEST(RelaxChart, ASidesCoarsestErrorIsTheSpannedGridsLevelError) {
  // A bump on side 0, the surface flat elsewhere: the error is set beside that side.
  auto bump = [](const Vec2& q) {
    const double z = std::exp(-40 * ((q.x - 0.3) * (q.x - 0.3) + q.y * q.y));
    const Vec3 n{80 * (q.x - 0.3) * z, 80 * q.y * z, 1};
    return SurfacePoint{{q.x, q.y, z}, n * (1 / norm(n))};
  };
  const auto side = relaxSide(kN, [&](double t) { return bump({t, 0}); }, kHow);
  for (const bool relaxed : {false, true}) {
    std::array<std::vector<double>, 4> sides = uniformSides();
    if (relaxed) sides[0] = side;
    EXPECT_EQ(coarsestRelaxedError(kN, 0, sides[0], bump, kHow, {}), levelError(5, spannedGridOfFive(sides), bump, {})) << relaxed;
  }
  EXPECT_NE(side[8], 0.25) << "the bump must move the side's coarsest relaxed texels";
}

// Level 2's centre on a narrow spike over a bowl: its triangles tent up over the bowl, farther from
// it than level 0's flat pair. Past the guard, the centre moves off the spike to where level 2 lies
// nearest, nearer than level 0; below it, the centre stays (the tile's uniform grid of 3).
TEST(RelaxChart, LevelTwosCentreLeavesASpikeThatTentsItOverABowl) {
  constexpr double kPi = 3.14159265358979323846;
  auto surface = [&](const Vec2& q) {
    const double bowl = -std::sin(kPi * q.x) * std::sin(kPi * q.y);
    const double spike = 1.2 * std::exp(-((q.x - 0.5) * (q.x - 0.5) + (q.y - 0.5) * (q.y - 0.5)) / 0.0004);
    return SurfacePoint{{q.x, q.y, bowl + spike}, {0, 0, 1}};  // levelError reads no normals
  };
  std::vector<ChartVertex> vertices;  // a lattice that misses the spike, as a coarse dense mesh would
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 20; ++i) {
      const Vec2 q{(i + 0.5) / 20, (j + 0.5) / 20};
      vertices.push_back({q, surface(q).position});
    }
  auto levelTwo = [&](const std::vector<Vec2>& q) {
    std::vector<Vec2> grid;
    for (std::uint32_t j = 0; j < kN; j += (kN - 1) / 2)
      for (std::uint32_t i = 0; i < kN; i += (kN - 1) / 2) grid.push_back(q[j * kN + i]);
    return grid;
  };
  const double levelZero = levelError(2, {{0, 0}, {1, 0}, {0, 1}, {1, 1}}, surface, vertices);
  const std::vector<Vec2> uniform{{0, 0}, {0.5, 0}, {1, 0}, {0, 0.5}, {0.5, 0.5}, {1, 0.5}, {0, 1}, {0.5, 1}, {1, 1}};
  const double uniformError = levelError(3, uniform, surface, vertices);
  ASSERT_GT(uniformError, levelZero) << "the spike must tent level 2 over the bowl";

  ChartRelaxing guarded = kHow;
  guarded.levelTwoGuard = 0.5 * uniformError;
  std::uint32_t nonConvex = 1;
  const auto moved = levelTwo(relaxChart(kN, surface, uniformSides(), guarded, &nonConvex, vertices));
  EXPECT_EQ(nonConvex, 0u);
  EXPECT_FALSE(moved[4].x == 0.5 && moved[4].y == 0.5) << "the centre must leave the spike";
  EXPECT_LT(levelError(3, moved, surface, vertices), levelZero);

  guarded.levelTwoGuard = uniformError;  // level 2 no farther than the guard: nothing moves
  const auto kept = levelTwo(relaxChart(kN, surface, uniformSides(), guarded, nullptr, vertices));
  for (std::size_t k = 0; k < uniform.size(); ++k) {
    EXPECT_EQ(kept[k].x, uniform[k].x) << k;
    EXPECT_EQ(kept[k].y, uniform[k].y) << k;
  }
}

// A grid with a ridge: the finest level of the relaxed charts lies closer to the dense surface, by
// CGAL's distance, than the tile's uniform grid does. (Charts of 17: at 9 a side, where the relaxed
// 5 x 5 grid is one level below the finest, the gain is 11 %.)
TEST(RelaxChart, TheFinestLevelFollowsCreasesCloser) {
  Mesh dense;
  constexpr int w = 40, h = 30;
  for (int j = 0; j <= h; ++j)
    for (int i = 0; i <= w; ++i) dense.positions.push_back({double(i), double(j), -0.8 * std::abs(i - 17.5 + 0.3 * j)});
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const std::uint32_t a = std::uint32_t(j * (w + 1) + i), b = a + 1, c = a + w + 2, d = a + w + 1;
      dense.addFace({a, b, c});
      dense.addFace({a, c, d});
    }
  multires::BaseMesh base = multires::simplifyStellar(dense, {.vertexRatio = 0.02});
  multires::pairTriangles(base, dense);
  auto finestError = [&](int sweeps) {
    ChartStats stats;
    const Atlas atlas = makeAtlas(dense, base, 17, &stats, sweeps);
    EXPECT_EQ(stats.nonConvexChartQuads, 0u);
    EXPECT_EQ(stats.coincidentTexels + stats.gapTexels + stats.borderDisagreements, 0u);
    return hausdorffDistance(reconstructLevel(base, atlas, maxLevel(17u)), dense, 20000).symmetric();
  };
  const double uniform = finestError(0), relaxed = finestError(kDefaultRelaxSweeps);
  EXPECT_LT(relaxed, uniform * 0.8) << "uniform " << uniform << ", relaxed " << relaxed;
}

}  // namespace
}  // namespace isoatlas::atlas

namespace isoatlas::atlas {
namespace {

// A crease along the tile's diagonal u = v (90 degrees), its normals those of the two flanks.
SurfacePoint diagonalRidge(const Vec2& q) {
  const double side = q.x < q.y ? -1 : 1;
  return {{q.x, q.y, -std::abs(q.x - q.y) / std::sqrt(2.0)}, Vec3{side, -side, std::sqrt(2.0)} * 0.5};
}

// With keepDiagonal, every texel on the diagonal stays exactly on it (u == v) while the others
// gather at the crease; without, relaxation moves some off it.
TEST(RelaxChart, AKeptDiagonalStaysOnTheDiagonal) {
  auto offDiagonal = [](const std::vector<Vec2>& q) {
    int off = 0;
    for (std::uint32_t i = 0; i < kN; ++i) off += q[std::size_t(i) * kN + i].x != q[std::size_t(i) * kN + i].y;
    return off;
  };
  ChartRelaxing keep = kHow;
  keep.keepDiagonal = true;
  const auto kept = relaxChart(kN, diagonalRidge, uniformSides(), keep);
  EXPECT_EQ(nonConvexQuads(kept), 0u);
  EXPECT_EQ(offDiagonal(kept), 0);
  EXPECT_GT(offDiagonal(relaxChart(kN, diagonalRidge, uniformSides(), kHow)), 0);
}

// An octahedron is its own base mesh: each tile two faces folded along its diagonal. Relaxed with
// the diagonals kept (make_atlas.cpp finds them: dense edges, and creases), every level of the
// model lies on the octahedron to float rounding; relaxation moving texels off a diagonal would cut
// the crease from level 6 up.
TEST(RelaxChart, APolyhedronThatIsItsOwnBaseIsExactAtEveryLevel) {
  Mesh dense;
  dense.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const auto& f : std::vector<std::array<std::uint32_t, 3>>{{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}})
    dense.addFace({f[0], f[1], f[2]});
  multires::BaseMesh base = multires::simplifyStellar(dense, {.vertexRatio = 1});
  ASSERT_EQ(base.vertexCount(), dense.vertexCount());
  multires::pairTriangles(base, dense);
  ChartStats stats;
  const Atlas atlas = makeAtlas(dense, base, 33, &stats);
  EXPECT_EQ(stats.keptDiagonals, 4u);
  for (int level = 0; level <= maxLevel(33u); level += 2)
    EXPECT_LT(hausdorffDistance(reconstructLevel(base, atlas, level), dense, 20000).symmetric(), 1e-5) << "level " << level;
}

}  // namespace
}  // namespace isoatlas::atlas
