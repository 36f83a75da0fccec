// triangulated / triangulatePolygon against polygons whose area and orientation are known: every
// triangle turns as the polygon does, the areas sum to the polygon's, and the triangles make a disc
// bounded by the polygon's own edges (so they cover it once).
#include <gtest/gtest.h>

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

// A comb: no corner sees the whole polygon, so no fan covers it once (ear clipping does).
TEST(Triangulated, ACombThatNoCornerSeesWholeIsClippedByEars) {
  const Mesh m = polygon({{0, 0, 0}, {5, 0, 0}, {5, 3, 0}, {4, 3, 0}, {4, 1, 0}, {3, 1, 0}, {3, 3, 0}, {2, 3, 0},
                          {2, 1, 0}, {1, 1, 0}, {1, 3, 0}, {0, 3, 0}});
  for (std::size_t apex = 0; apex < m.vertexCount(); ++apex) ASSERT_TRUE(fanTurns(m, apex, {0, 0, 1})) << apex;
  expectCoveredOnce(m, {0, 0, 1}, 11);
}

TEST(Triangulated, NewellNormalIsTwiceTheVectorArea) {
  const Mesh m = polygon({{0, 1, 0}, {1, 1, 0}, {1, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}});
  const Vec3 n = newellNormal(m.positions, m.face(0));
  EXPECT_DOUBLE_EQ(n.z, 6);
  EXPECT_DOUBLE_EQ(surfaceArea(m), 3);
}

}  // namespace
}  // namespace isoatlas
