// analyzeTopology against meshes whose topology is known by construction.
#include <gtest/gtest.h>

#include "core/mesh_topology.h"
#include "tests/test_util.h"

namespace isoatlas {
namespace {

TEST(MeshTopology, OctahedronIsAClosedSphere) {
  const MeshTopology t = analyzeTopology(test::octahedron());
  EXPECT_TRUE(t.closed);
  EXPECT_TRUE(t.manifold);
  EXPECT_TRUE(t.oriented);
  EXPECT_EQ(t.vertices, 6u);
  EXPECT_EQ(t.edges, 12u);
  EXPECT_EQ(t.euler, 2);
  EXPECT_EQ(t.genus, 0);
  EXPECT_EQ(t.components, 1u);
}

// Every edge of a closed, oriented octahedron has its partner; a face taken away leaves its three
// edges running one way only; an edge from a vertex to itself is not counted.
TEST(MeshTopology, DirectedEdgeBalanceFindsUnpartneredEdges) {
  Mesh m = test::octahedron();
  auto balance = directedEdgeBalance(m);
  EXPECT_EQ(balance.size(), 12u);
  for (const auto& [edge, count] : balance) EXPECT_EQ(count, 0) << edge.first << "-" << edge.second;
  Mesh open;
  open.positions = m.positions;
  for (std::size_t f = 1; f < m.faceCount(); ++f) open.addFace(m.face(f));
  open.addFace({0, 0, 1});
  int unmatched = 0;
  for (const auto& [edge, count] : directedEdgeBalance(open)) unmatched += std::abs(count);
  EXPECT_EQ(unmatched, 3);
}

TEST(MeshTopology, QuadTorusHasGenusOne) {
  const MeshTopology t = analyzeTopology(test::quadTorus(10, 7));
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.euler, 0);
  EXPECT_EQ(t.genus, 1);
}

TEST(MeshTopology, GridHasOneBoundaryLoop) {
  Mesh m;
  const int n = 4;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.positions.push_back({double(i), double(j), 0});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = std::uint32_t(j * (n + 1) + i);
      m.addFace({a, a + 1, a + n + 2});
      m.addFace({a, a + n + 2, a + n + 1});
    }
  const MeshTopology t = analyzeTopology(m);
  EXPECT_TRUE(t.manifold);
  EXPECT_FALSE(t.closed);
  EXPECT_EQ(t.boundaryEdges, 4u * n);
  EXPECT_EQ(t.boundaryLoops, 1u);
  EXPECT_EQ(t.euler, 1);
  EXPECT_EQ(t.genus, 0);
}

TEST(MeshTopology, TwoSpheresAreTwoComponents) {
  Mesh m = test::octahedron();
  const Mesh b = test::octahedron();
  const auto offset = std::uint32_t(m.vertexCount());
  for (const Vec3& p : b.positions) m.positions.push_back(p + Vec3{5, 0, 0});
  for (std::size_t f = 0; f < b.faceCount(); ++f) {
    auto face = b.face(f);
    m.addFace({face[0] + offset, face[1] + offset, face[2] + offset});
  }
  const MeshTopology t = analyzeTopology(m);
  EXPECT_EQ(t.components, 2u);
  EXPECT_EQ(t.euler, 4);
  EXPECT_EQ(t.genus, 0);
  EXPECT_TRUE(t.closed);
}

TEST(MeshTopology, BowtieVertexIsNonManifold) {
  // Two octahedra glued at one vertex: every edge is fine, the shared vertex has two fans.
  Mesh m = test::octahedron();
  const Mesh b = test::octahedron();
  const auto offset = std::uint32_t(m.vertexCount());
  for (const Vec3& p : b.positions) m.positions.push_back(p + Vec3{2, 0, 0});
  for (std::size_t f = 0; f < b.faceCount(); ++f) {
    std::uint32_t c[3];
    for (int i = 0; i < 3; ++i) c[i] = b.face(f)[i] == 1 ? 0 : b.face(f)[i] + offset;  // b's -x tip onto a's +x tip
    m.addFace({c[0], c[1], c[2]});
  }
  const MeshTopology t = analyzeTopology(m);
  EXPECT_EQ(t.nonManifoldEdges, 0u);
  EXPECT_EQ(t.nonManifoldVertices, 1u);
  EXPECT_FALSE(t.manifold);
  EXPECT_EQ(t.firstProblem, "vertex 0 joins two or more separate fans of faces");
}

TEST(MeshTopology, FlippedFaceIsNotOriented) {
  Mesh m = test::octahedron();
  std::swap(m.faceVertices[0], m.faceVertices[1]);
  const MeshTopology t = analyzeTopology(m);
  EXPECT_TRUE(t.manifold);
  EXPECT_FALSE(t.oriented);
}

TEST(MeshTopology, DegenerateFaceIsNamed) {
  Mesh m = test::octahedron();
  m.addFace({0, 0, 2});
  const MeshTopology t = analyzeTopology(m);
  EXPECT_FALSE(t.manifold);
  EXPECT_EQ(t.degenerateFaces, 1u);
}

}  // namespace
}  // namespace isoatlas
