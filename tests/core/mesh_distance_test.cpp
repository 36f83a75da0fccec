// core/distance: the Hausdorff and RMS distances on known shapes, and TriangleTree's closest points
// and ray crossings against brute force.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/distance/mesh_distance.h"
#include "core/distance/triangle_tree.h"
#include "core/error.h"
#include "core/mesh_topology.h"
#include "tests/multires/mesh_shapes.h"

namespace isoatlas {
namespace {

TEST(Hausdorff, KnownDistancesBothWays) {
  // Two concentric spheres of radii 10 and 10.5 (marching cubes, so each lies within a small
  // error of its radius): the distance is 0.5 both ways, within those errors.
  const Mesh a = test::sphereMesh(10);
  Mesh b = a;
  const Vec3 centre{12.3, 12.5, 12.2};
  for (Vec3& p : b.positions) p = centre + (p - centre) * (10.5 / 10);
  const Hausdorff h = hausdorffDistance(a, b, 20000);
  EXPECT_NEAR(h.aToB, 0.5, 0.06);
  EXPECT_NEAR(h.bToA, 0.5, 0.06);
  // The RMS of the same samples: also near 0.5, and never past the largest distance.
  EXPECT_NEAR(h.rmsAToB, 0.5, 0.06);
  EXPECT_NEAR(h.rmsBToA, 0.5, 0.06);
  EXPECT_LE(h.rms(), h.symmetric());
  // One mesh measured against many answers as measuring each pair afresh, bit for bit.
  const MeshDistances fromA(a, 20000);
  for (int k = 0; k < 2; ++k) {
    const Hausdorff reused = fromA.to(b);
    EXPECT_EQ(reused.aToB, h.aToB);
    EXPECT_EQ(reused.bToA, h.bToA);
    EXPECT_EQ(reused.rms(), h.rms());
  }
  EXPECT_LT(hausdorffDistance(a, a, 20000).symmetric(), 1e-12);
  // Seeded: the same figure every time (CGAL 5.5 placed points in faces with a generator seeded
  // from the clock).
  const Hausdorff again = hausdorffDistance(a, b, 20000);
  EXPECT_EQ(again.aToB, h.aToB);
  EXPECT_EQ(again.bToA, h.bToA);
  // A mesh moved by a known offset: the farthest sample lies at most that far.
  Mesh moved = a;
  for (Vec3& p : moved.positions) p.x += 0.25;
  const Hausdorff m = hausdorffDistance(a, moved, 20000);
  EXPECT_LE(m.symmetric(), 0.25 + 1e-9);
  EXPECT_GT(m.symmetric(), 0.2);
  EXPECT_LT(m.rms(), m.symmetric());  // most points of a sphere moved sideways lie nearer than 0.25
  EXPECT_NEAR(psnrDb(100, 1), 40, 1e-12);
  EXPECT_THROW(hausdorffDistance(Mesh{}, a), Error);
  // A point that is not finite is refused (CGAL's face sampler would never return).
  Mesh broken = a;
  broken.positions[3].y = std::nan("");
  EXPECT_THROW(hausdorffDistance(a, broken, 1000), Error);
  // A face Surface_mesh refuses is still measured, from a copy of its corners. A second copy of a
  // face (an edge of three faces) leaves the surface as it was; a chord across the sphere (three
  // vertices whose fans are closed) reaches deep inside it, and its points are that far from a.
  Mesh twice = a;
  const auto c = a.face(0);
  twice.addFace({c[0], c[1], c[2]});
  EXPECT_FALSE(analyzeTopology(twice).manifold);
  EXPECT_LT(hausdorffDistance(a, twice, 1000).symmetric(), 1e-12);
  EXPECT_LT(hausdorffDistance(twice, a, 1000).symmetric(), 1e-12);
  Mesh chord = a;
  const auto n = std::uint32_t(a.vertexCount());
  chord.addFace({0, n / 3, 2 * n / 3});
  const Hausdorff toChord = hausdorffDistance(a, chord, 1000);
  EXPECT_LT(toChord.aToB, 1e-12);  // a lies on chord's surface
  EXPECT_GT(toChord.bToA, 2.0);    // the chord's middle lies well inside a's sphere of radius 10
  // Only faces that name a vertex twice, or whose corners lie on one line, cover nothing: refused
  // (the draw by area would find no face).
  Mesh flat;
  flat.positions = a.positions;
  flat.addFace({0, 0, 1});
  EXPECT_THROW(hausdorffDistance(a, flat, 1000), Error);
  Mesh line;
  line.positions = {{0, 0, 0}, {1, 1, 1}, {3, 3, 3}};
  line.addFace({0, 1, 2});
  EXPECT_THROW(hausdorffDistance(a, line, 1000), Error);
  EXPECT_THROW(hausdorffDistance(line, a, 1000), Error);
}

// The closest point on triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5): the
// brute force TriangleTree is held to.
Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Whether the ray from o along d crosses triangle abc (Moller and Trumbore): the brute force the
// tree's crossings are held to, for rays that meet no edge.
bool rayCrosses(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a, p = cross(d, e2);
  const double det = dot(e1, p);
  if (std::abs(det) < 1e-14) return false;
  const Vec3 t = o - a;
  const double u = dot(t, p) / det;
  if (u < 0 || u > 1) return false;
  const Vec3 qv = cross(t, e1);
  const double v = dot(d, qv) / det;
  return v >= 0 && u + v <= 1 && dot(e2, qv) / det > 0;
}

double bruteDistance(const Mesh& mesh, const Vec3& q) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto c = mesh.face(f);
    best = std::min(best, norm(q - closestOnTriangle(q, mesh.positions[c[0]], mesh.positions[c[1]], mesh.positions[c[2]])));
  }
  return best;
}

// A torus of 14,400 triangles, so that the tree is many nodes deep: queries anywhere in its box and
// just off its surface, without a hint, with the last answer, and with a hint on the far side.
TEST(TriangleTree, ClosestPointsAsBruteForceWithOrWithoutAHint) {
  const Mesh torus = test::torusMesh(120, 60, 8, 3);
  const TriangleTree tree(torus);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> coordinate(-14, 14), offset(-0.05, 0.05);
  TriangleTree::Closest last = tree.closest(torus.positions[0]);
  const TriangleTree::Closest farSide = tree.closest({-11, 0, 0});
  for (int k = 0; k < 300; ++k) {
    const Vec3 v = torus.positions[random() % torus.vertexCount()];
    const Vec3 q = k % 2 == 0 ? Vec3{coordinate(random), coordinate(random), coordinate(random) / 3}
                              : v + Vec3{offset(random), offset(random), offset(random)};
    const double best = bruteDistance(torus, q);
    const TriangleTree::Closest found = tree.closest(q), hinted = tree.closest(q, last), misled = tree.closest(q, farSide);
    EXPECT_NEAR(norm(q - found.point), best, 1e-9);
    EXPECT_NEAR(norm(q - hinted.point), best, 1e-9);
    EXPECT_NEAR(norm(q - misled.point), best, 1e-9);
    EXPECT_NEAR(norm(q - tree.closestPoint(q, last.point)), best, 1e-9);
    EXPECT_NEAR(tree.distance(q), best, 1e-9);
    // The face named holds the point.
    const auto c = torus.face(found.face);
    EXPECT_NEAR(norm(found.point - closestOnTriangle(found.point, torus.positions[c[0]], torus.positions[c[1]], torus.positions[c[2]])), 0,
                1e-9);
    last = hinted;
  }
  // Rays from anywhere cross as many triangles as brute force counts.
  for (int k = 0; k < 100; ++k) {
    const Vec3 o{coordinate(random), coordinate(random), coordinate(random) / 3};
    const Vec3 d{coordinate(random), coordinate(random), coordinate(random)};
    std::size_t crossed = 0;
    for (std::size_t f = 0; f < torus.faceCount(); ++f) {
      const auto c = torus.face(f);
      crossed += rayCrosses(o, d, torus.positions[c[0]], torus.positions[c[1]], torus.positions[c[2]]) ? 1 : 0;
    }
    EXPECT_EQ(tree.crossings(o, d), crossed) << "ray " << k;
  }
}

TEST(TriangleTree, NamesFacesOfTheMeshAndCountsCrossings) {
  // A face that names a vertex twice is left out, and the faces after it keep their indices.
  Mesh sphere = test::sphereMesh(10);
  Mesh withDegenerate;
  withDegenerate.positions = sphere.positions;
  withDegenerate.addFace({0, 0, 1});
  for (std::size_t f = 0; f < sphere.faceCount(); ++f) {
    const auto c = sphere.face(f);
    withDegenerate.addFace({c[0], c[1], c[2]});
  }
  const TriangleTree tree(withDegenerate);
  const TriangleTree::Closest hint{sphere.positions[0], 1};
  for (std::size_t f = 0; f < sphere.faceCount(); f += 97) {
    const auto c = sphere.face(f);
    const Vec3 centre = (sphere.positions[c[0]] + sphere.positions[c[1]] + sphere.positions[c[2]]) * (1.0 / 3);
    EXPECT_EQ(tree.closest(centre, hint).face, f + 1);
  }
  // A ray from inside a closed surface crosses it an odd number of times, from outside an even one.
  const Vec3 centre{12.3, 12.5, 12.2}, direction{0.5773, 0.5802, 0.5743};
  EXPECT_EQ(tree.crossings(centre, direction), 1u);
  EXPECT_EQ(tree.crossings(centre + Vec3{0, 0, 15}, direction), 0u);
  EXPECT_EQ(tree.crossings(centre - direction * 15, direction), 2u);
  Mesh quads;
  quads.positions = sphere.positions;
  quads.addFace({0, 1, 2, 3});
  EXPECT_THROW(TriangleTree{quads}, Error);
  Mesh flat;
  flat.positions = sphere.positions;
  flat.addFace({0, 0, 1});
  EXPECT_THROW(TriangleTree{flat}, Error);
}

}  // namespace
}  // namespace isoatlas
