// triangulated / triangulatePolygon against polygons whose area and orientation are known: every
// triangle turns as the polygon does, the areas sum to the polygon's, and the triangles make a disc
// bounded by the polygon's own edges (so they cover it once).
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <utility>

#include "core/mesh.h"
#include "core/mesh_topology.h"
#include "core/polygon_triangulation.h"

namespace isoatlas {
namespace {

Mesh polygon(const std::vector<Vec3>& corners) {
  Mesh m;
  m.positions = corners;
  std::vector<std::uint32_t> face(corners.size());
  for (std::uint32_t i = 0; i < face.size(); ++i) face[i] = i;
  m.addFace(face);
  return m;
}

// Whether the fan round `apex` has a triangle of no area or turned against `normal`.
bool fanTurns(const Mesh& m, std::size_t apex, const Vec3& normal) {
  const std::size_t k = m.vertexCount();
  for (std::size_t i = 1; i + 1 < k; ++i) {
    const Vec3 &a = m.positions[apex], &b = m.positions[(apex + i) % k], &c = m.positions[(apex + i + 1) % k];
    if (!(dot(cross(b - a, c - a), normal) > 1e-9)) return true;
  }
  return false;
}

void expectCoveredOnce(const Mesh& m, const Vec3& normal, double area) {
  const Mesh t = triangulated(m);
  const std::size_t k = m.vertexCount();
  ASSERT_EQ(t.faceCount(), k - 2);
  double sum = 0;
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (std::size_t f = 0; f < t.faceCount(); ++f) {
    const auto c = t.face(f);
    const double turn = dot(cross(t.positions[c[1]] - t.positions[c[0]], t.positions[c[2]] - t.positions[c[0]]), normal);
    EXPECT_GT(turn, 1e-9 * area) << "triangle " << f << " has no area or turns over";
    sum += turn / 2;
    for (int e = 0; e < 3; ++e) edges.insert({c[e], c[(e + 1) % 3]});
  }
  EXPECT_NEAR(sum, area, 1e-9 * area);
  const MeshTopology topology = analyzeTopology(t);
  EXPECT_TRUE(topology.manifold) << topology.firstProblem;
  EXPECT_TRUE(topology.oriented);
  EXPECT_EQ(topology.euler, 1);  // a disc
  EXPECT_EQ(topology.boundaryEdges, k);
  for (std::uint32_t i = 0; i < k; ++i)
    EXPECT_TRUE(edges.count({i, std::uint32_t((i + 1) % k)})) << "the polygon's edge " << i << " is not on the disc's border";
}

TEST(Triangulated, NoTriangleOfNoAreaWhereThreeCornersLieOnALine) {
  const Mesh m = polygon({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}});  // (1, 0, 0) mid-side
  ASSERT_TRUE(fanTurns(m, 0, {0, 0, 1}));  // round its first corner, (0, 1, 2) has no area
  expectCoveredOnce(m, {0, 0, 1}, 4);
  // A polygon whose first corner's fan is fine keeps it.
  const Mesh s = triangulated(polygon({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}));
  EXPECT_EQ(s.face(0)[0], 0u);
  EXPECT_EQ(s.face(1)[0], 0u);
}

// corner_poly.off's L-shaped hexagon: round its first corner one triangle turns over.
TEST(Triangulated, AnLShapeSplitsRoundTheCornerThatSeesItAll) {
  const Mesh m = polygon({{0, 1, 0}, {1, 1, 0}, {1, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}});
  ASSERT_TRUE(fanTurns(m, 0, {0, 0, 1}));
  expectCoveredOnce(m, {0, 0, 1}, 3);
  // The same far from the origin and in a tilted plane.
  const Vec3 u = unit({1, 1, 0}), v = unit({-0.1, 0.1, 1}), n = unit(cross(u, v));
  std::vector<Vec3> tilted;
  for (const Vec3& p : m.positions) tilted.push_back(Vec3{1e5, -2e5, 3e5} + u * p.x + v * p.y);
  expectCoveredOnce(polygon(tilted), n, 3);
}

// A comb of `prongs` prongs (1 wide, 2 tall, 1 apart, on a base 1 tall): no corner sees it whole,
// so no fan covers it once. 4 prongs is split by the largest smallest triangle, 17 (68 corners) by
// ear clipping.
Mesh comb(int prongs) {
  std::vector<Vec3> corners{{0, 0, 0}, {2.0 * prongs - 1, 0, 0}};
  for (int p = prongs - 1; p >= 0; --p) {
    corners.push_back({2.0 * p + 1, 3, 0}), corners.push_back({2.0 * p, 3, 0});
    if (p > 0) corners.push_back({2.0 * p, 1, 0}), corners.push_back({2.0 * p - 1, 1, 0});
  }
  return polygon(corners);
}

TEST(Triangulated, ACombThatNoCornerSeesWholeIsCoveredOnce) {
  for (const int prongs : {3, 17}) {
    const Mesh m = comb(prongs);
    for (std::size_t apex = 0; apex < m.vertexCount(); ++apex) ASSERT_TRUE(fanTurns(m, apex, {0, 0, 1})) << apex;
    expectCoveredOnce(m, {0, 0, 1}, 4.0 * prongs - 1);
  }
}

// A corner a hair off a straight side (as a file's rounding leaves a mid-side vertex): the fan round
// the first corner is valid but lays a sliver, which maps a stretch of a chart onto a line; the split
// whose smallest triangle is largest has none.
TEST(Triangulated, ACornerAHairOffASideGetsNoSliver) {
  const auto smallest = [](const Mesh& t) {
    double least = 1e300;
    for (std::size_t f = 0; f < t.faceCount(); ++f) {
      const auto c = t.face(f);
      least = std::min(least, cross(t.positions[c[1]] - t.positions[c[0]], t.positions[c[2]] - t.positions[c[0]]).z);
    }
    return least;
  };
  const Mesh m = polygon({{0, 0, 0}, {1, -1e-9, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}});
  ASSERT_FALSE(fanTurns(m, 0, {0, 0, 1}));  // valid round its first corner, with (0, 1, 2) of 2e-9
  expectCoveredOnce(m, {0, 0, 1}, 4 + 1e-9);
  EXPECT_GT(smallest(triangulated(m)), 0.5);
  // The same in float32 decimals: (0.4, 0.35) lies on the side from (0.1, 0.2) to (0.7, 0.5) to rounding.
  std::vector<Vec3> rounded;
  for (const auto& [x, y] : std::vector<std::pair<float, float>>{{0.1f, 0.2f}, {0.4f, 0.35f}, {0.7f, 0.5f}, {0.5f, 0.9f}, {0, 0.6f}})
    rounded.push_back({double(x), double(y), 0});
  const Mesh r = polygon(rounded);
  EXPECT_GT(smallest(triangulated(r)), 1e-3 * newellNormal(r.positions, r.face(0)).z);
}

// Every triangle of `t` turns along +z by more than `least` (twice-area), none repeats a vertex, and
// their areas sum to `area`.
void expectTurnedUpSumming(const Mesh& t, double least, double area) {
  double sum = 0;
  for (std::size_t f = 0; f < t.faceCount(); ++f) {
    const auto c = t.face(f);
    EXPECT_TRUE(c[0] != c[1] && c[1] != c[2] && c[2] != c[0]) << "triangle " << f << " repeats a vertex";
    const double turn = cross(t.positions[c[1]] - t.positions[c[0]], t.positions[c[2]] - t.positions[c[0]]).z;
    EXPECT_GT(turn, least) << "triangle " << f;
    sum += turn / 2;
  }
  EXPECT_NEAR(sum, area, 1e-9 * area);
}

// Polygons that meet themselves at a vertex (a review's cases; no corpus mesh has one): each loop is
// split alone. Through the fans and ears, both ended in the fallback fan, which turned triangles over.
TEST(Triangulated, APolygonThatMeetsItselfIsSplitIntoItsLoops) {
  // A spike out of vertex 2 to vertex 3 and back: the spike has no area and gives no triangle.
  Mesh spike;
  spike.positions = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {3, 1, 0}, {2, 2, 0}, {0, 2, 0}};
  spike.addFace({0, 1, 2, 3, 2, 4, 5});
  const Mesh s = triangulated(spike);
  EXPECT_EQ(s.faceCount(), 3u);
  expectTurnedUpSumming(s, 1e-9, 4);
  // Two squares meeting at a corner, one polygon round both.
  Mesh squares;
  squares.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}, {0, 1, 0}};
  squares.addFace({0, 1, 2, 3, 4, 5, 2, 6});
  const Mesh q = triangulated(squares);
  EXPECT_EQ(q.faceCount(), 4u);
  expectTurnedUpSumming(q, 1e-9, 2);
  // A face of fewer than three corners (a mesh built in code) gives no triangle and no normal.
  Mesh two;
  two.positions = {{0, 0, 0}, {1, 0, 0}};
  EXPECT_TRUE(triangulatePolygon(two.positions, std::vector<std::uint32_t>{0, 1}).empty());
  EXPECT_EQ(norm(newellNormal(two.positions, std::vector<std::uint32_t>{})), 0);
}

// Past 64 corners (no optimal split): a corner a hair off a side, beside the first corner, lays a
// sliver in the first corner's fan; ear clipping, the best shaped ear first, lays none.
TEST(Triangulated, ALargePolygonsCornerAHairOffASideGetsNoSliver) {
  std::vector<Vec3> corners{{1, 0, 0}};
  const Vec3 next{std::cos(2 * M_PI / 80), std::sin(2 * M_PI / 80), 0};
  corners.push_back((corners[0] + next) * (0.5 + 1e-6));  // mid-chord, a hair outwards
  for (int i = 1; i < 80; ++i) corners.push_back({std::cos(2 * M_PI * i / 80), std::sin(2 * M_PI * i / 80), 0});
  const Mesh m = polygon(corners);
  ASSERT_FALSE(fanTurns(m, 0, {0, 0, 1}));  // valid round its first corner, with (0, 1, 2) a sliver
  const double area = newellNormal(m.positions, m.face(0)).z / 2;
  expectCoveredOnce(m, {0, 0, 1}, area);
  expectTurnedUpSumming(triangulated(m), 1e-6, area);
}

TEST(Triangulated, NewellNormalIsTwiceTheVectorArea) {
  const Mesh m = polygon({{0, 1, 0}, {1, 1, 0}, {1, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}});
  const Vec3 n = newellNormal(m.positions, m.face(0));
  EXPECT_DOUBLE_EQ(n.z, 6);
  EXPECT_DOUBLE_EQ(surfaceArea(m), 3);
}

}  // namespace
}  // namespace isoatlas
