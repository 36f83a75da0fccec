// Stellar operators and simplification against invariants: manifoldness, genus and boundary loops
// kept, a weld undone by a split (and back), every dense vertex parametrised inside its base face.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "core/error.h"
#include "core/mesh_topology.h"
#include "core/distance/mesh_distance.h"
#include "multires/stellar_simplify.h"
#include "tests/multires/mesh_shapes.h"
#include "tests/multires/parametrisation_checks.h"
#include "tests/test_util.h"
#include "tests/thread_count.h"

namespace isoatlas::multires {
namespace {

using test::torusMesh;

// Faces as sorted vertex-triple keys, to compare connectivity.
std::vector<std::array<int, 3>> faceSet(const StellarMesh& m) {
  std::vector<std::array<int, 3>> faces;
  for (const FaceH f : m.faces()) {
    std::array<int, 3> t{};
    int i = 0;
    for (const VertexH v : m.fv_range(f)) t[i++] = v.idx();
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());  // keep orientation
    faces.push_back(t);
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

TEST(StellarOperators, SplitThenEdgeWeldRestoresTheConnectivity) {
  StellarMesh m = toStellarMesh(torusMesh(8, 6), "torus");
  const auto before = faceSet(m);
  for (int e = 0; e < 20; ++e) {
    const EdgeH edge(e);
    const VertexH a = m.from_vertex_handle(m.halfedge_handle(edge, 0));
    const Vec3 mid = (toVec3(m.point(a)) + toVec3(m.point(m.to_vertex_handle(m.halfedge_handle(edge, 0))))) * 0.5;
    const VertexH v = splitEdge(m, edge, mid);
    EXPECT_EQ(m.valence(v), 4u);
    ASSERT_TRUE(canWeldInto(m, v, a));
    const WeldCounts counts = weldInto(m, v, a);
    EXPECT_EQ(counts.edgeWelds, 1);
    EXPECT_EQ(counts.flips, 0);
    m.garbage_collection();
    EXPECT_EQ(faceSet(m), before);
  }
}

TEST(StellarOperators, FlipsBringADegreeSixVertexToAnEdgeWeld) {
  StellarMesh m = toStellarMesh(torusMesh(10, 8), "torus");
  const VertexH v(27);
  const OneRing ring = oneRing(m, v);
  ASSERT_EQ(ring.vertices.size(), 6u);
  ASSERT_TRUE(canWeldInto(m, v, ring.vertices[0]));
  const WeldCounts counts = weldInto(m, v, ring.vertices[0]);
  EXPECT_EQ(counts.flips, 2);
  EXPECT_EQ(counts.edgeWelds, 1);
  const MeshTopology t = analyzeTopology(toMesh(m));
  EXPECT_TRUE(t.closed && t.manifold && t.oriented) << t.firstProblem;
  EXPECT_EQ(t.genus, 1);
  EXPECT_EQ(t.vertices, 79u);
}

TEST(StellarOperators, EdgeWeldThenSplitRestoresTheConnectivity) {
  // Make a degree-4 vertex by splitting a grid diagonal; weld it, split the edge it leaves again.
  StellarMesh g = toStellarMesh(test::gridMesh(6, 6, [](int, int) { return false; }), "grid");
  const VertexH p(2 * 7 + 2), q(3 * 7 + 3);
  const HalfedgeH h = g.find_halfedge(p, q);
  ASSERT_TRUE(h.is_valid());
  const Vec3 mid{2.5, 2.5, toVec3(g.point(p)).z * 0.5 + toVec3(g.point(q)).z * 0.5};
  const VertexH w = splitEdge(g, g.edge_handle(h), mid);
  const auto before = faceSet(g);
  ASSERT_TRUE(canWeldInto(g, w, p));
  const WeldCounts counts = weldInto(g, w, p);
  EXPECT_EQ(counts.edgeWelds, 1);
  g.garbage_collection();
  const HalfedgeH left = g.find_halfedge(p, q);
  ASSERT_TRUE(left.is_valid()) << "the weld leaves the edge the split had cut";
  const VertexH again = splitEdge(g, g.edge_handle(left), mid);
  EXPECT_EQ(again.idx(), w.idx());
  EXPECT_EQ(faceSet(g), before);
}

TEST(StellarOperators, RandomFlipsKeepTheMeshManifoldAndItsGenus) {
  StellarMesh m = toStellarMesh(torusMesh(12, 8), "torus");
  std::mt19937 rng(5);
  int flips = 0;
  for (int i = 0; i < 2000; ++i) {
    const EdgeH e(int(rng() % m.n_edges()));
    if (m.is_flip_ok(e)) m.flip(e), ++flips;
  }
  EXPECT_GT(flips, 1000);
  const MeshTopology t = analyzeTopology(toMesh(m));
  EXPECT_TRUE(t.closed && t.manifold && t.oriented) << t.firstProblem;
  EXPECT_EQ(t.genus, 1);
}

TEST(StellarOperators, WeldsKeepTheDegreeTableCurrent) {
  // A torus and a sheet with holes (boundary welds): random valid welds, each checked with and
  // without the table, which must then equal a fresh count.
  for (StellarMesh m : {toStellarMesh(torusMesh(14, 10), "torus"),
                        toStellarMesh(test::gridMesh(9, 9, [](int i, int j) { return (i == 3 || i == 6) && j == 4; }), "grid")}) {
    DegreeTable degrees = degreeTable(m);
    std::mt19937 rng(11);
    int welds = 0;
    for (int attempt = 0; attempt < 4000 && welds < 60; ++attempt) {
      const VertexH v(int(rng() % m.n_vertices()));
      if (m.status(v).deleted()) continue;
      const OneRing ring = oneRing(m, v);
      if (ring.vertices.empty()) continue;
      const VertexH u = ring.vertices[rng() % ring.vertices.size()];
      const bool can = canWeldInto(m, v, u);
      ASSERT_EQ(canWeldInto(m, v, u, &degrees), can);
      if (!can) continue;
      weldInto(m, v, u, &degrees);
      ++welds;
      ASSERT_EQ(degrees, degreeTable(m)) << "after weld " << welds;  // both 0 for welded vertices
    }
    EXPECT_EQ(welds, 60);
    const MeshTopology t = analyzeTopology(toMesh(m));
    EXPECT_TRUE(t.manifold && t.oriented) << t.firstProblem;
  }
}

void expectParametrisation(const Mesh& dense, const BaseMesh& base, double tolerance) {
  test::expectParametrisationInside(dense, base, tolerance);
  for (std::size_t i = 0; i < base.vertexCount(); ++i) {
    ASSERT_GE(base.denseVertex[i], 0);
    EXPECT_EQ(base.positions[i], dense.positions[std::size_t(base.denseVertex[i])]) << "base vertices are original";
    const std::size_t d = std::size_t(base.denseVertex[i]);
    EXPECT_EQ(norm(base.pointAt(base.denseTriangle[d], base.denseBary[d]) - base.positions[i]), 0.0);
  }
}

void expectSameTopology(const Mesh& dense, const Mesh& simplified) {
  const MeshTopology a = analyzeTopology(dense), b = analyzeTopology(simplified);
  EXPECT_TRUE(b.manifold) << b.firstProblem;
  EXPECT_TRUE(b.oriented);
  EXPECT_EQ(b.closed, a.closed);
  EXPECT_EQ(b.genus, a.genus);
  EXPECT_EQ(b.boundaryLoops, a.boundaryLoops);
  EXPECT_EQ(b.components, a.components);
}

TEST(StellarSimplify, TorusKeepsGenusAndReachesTheRatio) {
  const Mesh dense = torusMesh(80, 40);
  SimplifyStats stats;
  const BaseMesh base = simplifyStellar(dense, {.vertexRatio = 0.02}, &stats);
  EXPECT_TRUE(stats.reachedTarget);
  EXPECT_EQ(base.vertexCount(), 64u);
  EXPECT_GT(stats.operators.faceWelds + stats.operators.edgeWelds, 3000);
  EXPECT_GT(stats.operators.flips, 0);
  expectSameTopology(dense, base.triangleMesh());
  expectParametrisation(dense, base, 0.5);  // the minor radius is 1
}

TEST(StellarSimplify, TheDefaultBaseSizeIsTwoPercentUpToAThousandNeverUnderOnePercentAndASmallMeshWhole) {
  EXPECT_EQ(defaultBaseVertices(2775), 56u);      // 2 %
  EXPECT_EQ(defaultBaseVertices(50000), 1000u);   // 2 %, at the cap
  EXPECT_EQ(defaultBaseVertices(80000), 1000u);   // capped, still above 1 %
  EXPECT_EQ(defaultBaseVertices(385000), 3850u);  // 1 %
  EXPECT_EQ(defaultBaseVertices(101), 4u);        // never below 4
  EXPECT_EQ(defaultBaseVertices(100), 100u);      // a small mesh is its own base mesh
  EXPECT_EQ(defaultBaseVertices(8), 8u);
  SimplifyStats stats;
  simplifyStellar(torusMesh(80, 40), {}, &stats);  // 3200 vertices
  EXPECT_EQ(stats.targetVertices, 64u);
  EXPECT_TRUE(stats.reachedTarget);
  // An octahedron is its own base mesh: every vertex and triangle where it was.
  const Mesh octahedron = test::octahedron();
  const BaseMesh whole = simplifyStellar(octahedron);
  ASSERT_EQ(whole.vertexCount(), 6u);
  ASSERT_EQ(whole.triangleCount(), 8u);
  std::set<std::array<double, 3>> dense, base;
  for (const Vec3& p : octahedron.positions) dense.insert({p.x, p.y, p.z});
  for (const Vec3& p : whole.positions) base.insert({p.x, p.y, p.z});
  EXPECT_EQ(base, dense);
}

TEST(StellarSimplify, DoubleTorusKeepsGenusTwo) {
  const Mesh dense = test::doubleTorusMesh();
  ASSERT_EQ(analyzeTopology(dense).genus, 2);
  SimplifyStats stats;
  const BaseMesh base = simplifyStellar(dense, {.vertexRatio = 0.03}, &stats);
  expectSameTopology(dense, base.triangleMesh());
  expectParametrisation(dense, base, 2.0);  // tube radius 3.2 voxels
  EXPECT_LT(base.vertexCount(), dense.vertexCount() / 10);
}

TEST(StellarSimplify, TheBaseMeshDoesNotDependOnTheThreadCount) {
  // Rankings near the target size run in parallel; the welds must still come in one order.
  const Mesh dense = test::doubleTorusMesh();
  auto simplify = [&] { return simplifyStellar(dense, {.vertexRatio = 0.03}); };
  const BaseMesh one = test::onThreads(1, simplify);
  for (const int threads : {2, 8}) {
    const BaseMesh m = test::onThreads(threads, simplify);
    EXPECT_EQ(m.positions, one.positions) << threads << " threads";
    EXPECT_EQ(m.triangles, one.triangles) << threads << " threads";
    EXPECT_EQ(m.denseTriangle, one.denseTriangle) << threads << " threads";
    EXPECT_EQ(m.denseBary, one.denseBary) << threads << " threads";
  }
}

TEST(StellarSimplify, BoundariesAreWeldedAlongThemselves) {
  // A wavy sheet with three square holes: four boundary loops, kept; corners stay on the border.
  const Mesh dense = test::gridMesh(40, 30, [](int i, int j) {
    return (i >= 8 && i < 12 && j >= 8 && j < 12) || (i >= 25 && i < 31 && j >= 5 && j < 9) ||
           (i >= 15 && i < 18 && j >= 20 && j < 26);
  });
  ASSERT_EQ(analyzeTopology(dense).boundaryLoops, 4u);
  SimplifyStats stats;
  const BaseMesh base = simplifyStellar(dense, {.vertexRatio = 0.05}, &stats);
  EXPECT_GT(stats.operators.boundaryWelds, 50);
  // A boundary vertex lies on its ring's border exactly, so its welds are not refused by rounding.
  EXPECT_TRUE(stats.reachedTarget);
  EXPECT_LT(stats.refusals.pointOutside, 5u);
  expectSameTopology(dense, base.triangleMesh());
  // 1.5 grid cells: untangling moves a few vertices' parameters across a fold, about a cell.
  expectParametrisation(dense, base, 1.5);
  // The outer border keeps its course: all four corners of the sheet are still base vertices.
  for (const auto& corner : {std::pair{0.0, 0.0}, {40.0, 0.0}, {0.0, 30.0}, {40.0, 30.0}})
    EXPECT_TRUE(std::any_of(base.positions.begin(), base.positions.end(),
                            [&](const Vec3& p) { return p.x == corner.first && p.y == corner.second; }))
        << "corner " << corner.first << ", " << corner.second;
}

TEST(StellarSimplify, ErrorBoundStopsEarly) {
  const Mesh dense = test::sphereMesh(10);
  SimplifyStats loose, tight;
  const BaseMesh a = simplifyStellar(dense, {.vertexRatio = 0.01}, &loose);
  const BaseMesh b = simplifyStellar(dense, {.vertexRatio = 0.01, .maxError = 0.05}, &tight);
  EXPECT_FALSE(tight.reachedTarget);
  EXPECT_GT(b.vertexCount(), a.vertexCount());
  expectSameTopology(dense, b.triangleMesh());
  // The bound is on each weld's RMS distance to the planes it replaced: the dense surface stays that
  // close on average, where the unbounded run strays past it.
  const Hausdorff boundedDistance = hausdorffDistance(dense, b.triangleMesh());
  const Hausdorff looseDistance = hausdorffDistance(dense, a.triangleMesh());
  EXPECT_LE(boundedDistance.rmsAToB, 0.05);
  EXPECT_GT(looseDistance.rmsAToB, 0.05);
}

TEST(StellarSimplify, RejectsNonManifoldInputSayingWhere) {
  Mesh bowtie;
  bowtie.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  bowtie.addFace({0, 1, 2});
  bowtie.addFace({0, 3, 4});
  try {
    simplifyStellar(bowtie);
    FAIL() << "a non-manifold mesh was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.exitCode(), 2);
    EXPECT_NE(std::string(e.what()).find("vertex"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace isoatlas::multires
