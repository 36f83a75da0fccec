// The side of a mesh from its closest point's pseudonormal (edit/dvt/mesh_sign.h), against
// brute force and analytic shapes: tori and a sphere with a cavity, each stored both ways round.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <array>

#include "edit/solids/mesh_sign.h"
#include "edit/solids/mesh_solid.h"

namespace isoatlas::edit::dvt {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(MeshSign, ClosestOnTriangleIsNoFartherThanAnyPointOfItAndNamesItsFeature) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  auto random = [&] { return Vec3{u(rng), u(rng), u(rng)}; };
  int features[7] = {};
  for (int trial = 0; trial < 2000; ++trial) {
    const Vec3 corner[3] = {random(), random(), random()}, p = random() * 2;
    const ClosestOnTriangle c = closestOnTriangle(p, corner[0], corner[1], corner[2]);
    ++features[c.feature];
    const double d = norm(p - c.point);
    const int n = 40;  // a lattice of the triangle's points, none of them closer
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Vec3 q = corner[0] + (corner[1] - corner[0]) * (double(i) / n) + (corner[2] - corner[0]) * (double(j) / n);
        ASSERT_LE(d, norm(p - q) + 1e-12);
      }
    if (c.feature < kEdgeFeature) {
      EXPECT_EQ(norm(c.point - corner[c.feature]), 0.0);
    } else if (c.feature < kFaceFeature) {  // on the edge's segment, off both its ends
      const Vec3 a = corner[c.feature - kEdgeFeature], b = corner[(c.feature - kEdgeFeature + 1) % 3];
      EXPECT_NEAR(norm(cross(c.point - a, b - a)), 0, 1e-12);
      EXPECT_GT(dot(c.point - a, b - a), 0);
      EXPECT_GT(dot(c.point - b, a - b), 0);
    } else {  // straight above the triangle
      const Vec3 normal = unit(cross(corner[1] - corner[0], corner[2] - corner[0]));
      EXPECT_NEAR(norm(cross(p - c.point, normal)), 0, 1e-9);
    }
  }
  for (int f = 0; f < 7; ++f) EXPECT_GT(features[f], 20) << "feature " << f;
}

// A closed grid of (u, v) in [0, nu) x [0, nv), wrapped in u, two triangles a cell; `at` places a
// vertex, and rows v = 0 and v = nv close on themselves when `poles` (a sphere's).
Mesh gridMesh(int nu, int nv, bool wrapV, const std::function<Vec3(int, int)>& at) {
  Mesh m;
  const int rows = wrapV ? nv : nv + 1;
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < nu; ++u) m.positions.push_back(at(u, v));
  auto id = [&](int u, int v) { return std::uint32_t((v % rows) * nu + (u % nu)); };
  for (int v = 0; v < nv; ++v)
    for (int u = 0; u < nu; ++u) {
      m.addFace({id(u, v), id(u + 1, v), id(u + 1, v + 1)});
      m.addFace({id(u, v), id(u + 1, v + 1), id(u, v + 1)});
    }
  return m;
}

Mesh torus(double major, double minor, int nu, int nv) {
  return gridMesh(nu, nv, true, [&](int u, int v) {
    const double a = 2 * kPi * u / nu, b = 2 * kPi * v / nv, ring = major + minor * std::cos(b);
    return Vec3{ring * std::cos(a), ring * std::sin(a), minor * std::sin(b)};
  });
}

// A UV sphere: a pole vertex at each end and rings between, fans at the poles.
Mesh sphere(double radius, int nu, int nv) {
  Mesh m;
  m.positions.push_back({0, 0, -radius});
  for (int v = 1; v < nv; ++v)
    for (int u = 0; u < nu; ++u) {
      const double a = 2 * kPi * u / nu, b = kPi * v / nv - kPi / 2;
      m.positions.push_back({radius * std::cos(b) * std::cos(a), radius * std::cos(b) * std::sin(a), radius * std::sin(b)});
    }
  m.positions.push_back({0, 0, radius});
  const std::uint32_t top = std::uint32_t(m.positions.size() - 1);
  auto id = [&](int u, int v) { return std::uint32_t(1 + (v - 1) * nu + (u % nu)); };
  for (int u = 0; u < nu; ++u) {
    m.addFace({0, id(u + 1, 1), id(u, 1)});
    m.addFace({top, id(u, nv - 1), id(u + 1, nv - 1)});
    for (int v = 1; v + 1 < nv; ++v) {
      m.addFace({id(u, v), id(u + 1, v), id(u + 1, v + 1)});
      m.addFace({id(u, v), id(u + 1, v + 1), id(u, v + 1)});
    }
  }
  return m;
}

Mesh reversed(Mesh m) {
  for (std::size_t f = 0; f < m.faceCount(); ++f) std::swap(m.faceVertices[m.faceOffsets[f] + 1], m.faceVertices[m.faceOffsets[f] + 2]);
  return m;
}

Mesh merged(const Mesh& a, const Mesh& b) {
  Mesh m = a;
  const std::uint32_t base = std::uint32_t(a.positions.size());
  m.positions.insert(m.positions.end(), b.positions.begin(), b.positions.end());
  for (std::size_t f = 0; f < b.faceCount(); ++f) {
    const auto c = b.face(f);
    m.addFace({c[0] + base, c[1] + base, c[2] + base});
  }
  return m;
}

// Whether p is inside the mesh by the parity of a ray's crossings, triangle by triangle (Moller and
// Trumbore's test): the mesh's own inside, which the probes of PseudoNormals ask for.
bool insideByParity(const Mesh& m, const Vec3& p) {
  const Vec3 dir = unit(Vec3{0.5773, 0.5802, 0.5743});
  int crossings = 0;
  for (std::size_t f = 0; f < m.faceCount(); ++f) {
    const auto c = m.face(f);
    const Vec3 a = m.positions[c[0]], e1 = m.positions[c[1]] - a, e2 = m.positions[c[2]] - a;
    const Vec3 h = cross(dir, e2);
    const double det = dot(e1, h);
    if (std::abs(det) < 1e-15) continue;
    const Vec3 s = p - a;
    const double u = dot(s, h) / det;
    const Vec3 q = cross(s, e1);
    const double v = dot(dir, q) / det;
    if (u >= 0 && v >= 0 && u + v <= 1 && dot(e2, q) / det > 0) ++crossings;
  }
  return crossings % 2 == 1;
}

struct Shape {
  std::string name;
  Mesh mesh;
  std::function<double(const Vec3&)> distance;  // analytic signed distance, < 0 inside
  std::function<Vec3(const Vec3&)> normal;       // analytic outward normal near the surface; none: sharp
};

// Every point's sign, from a closest face found by brute force, against the analytic shape: random
// points away from the surface (farther than the mesh's chords sag), and points a little off each
// vertex and each edge's middle, on both sides, where the vertex and edge pseudonormals decide.
void expectSignsOf(const Shape& shape, double sag) {
  SCOPED_TRACE(shape.name);
  const PseudoNormals normals(shape.mesh, [&](const Vec3& p) { return insideByParity(shape.mesh, p); });
  ASSERT_TRUE(normals.usable());
  std::vector<Vec3> points;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.6, 1.6);
  while (points.size() < 1500) {
    const Vec3 p{u(rng), u(rng), u(rng) * 0.6};
    if (std::abs(shape.distance(p)) > 2 * sag) points.push_back(p);
  }
  // A polyhedron's points go every way from its corners and edges: where faces meet at a sharp angle,
  // a face's own normal would put some of them on the wrong side.
  const double offset = shape.normal ? 3 * sag : 0.05;
  std::normal_distribution<double> g;
  for (std::size_t f = 0; f < shape.mesh.faceCount(); f += shape.normal ? 2 : 1) {
    const auto c = shape.mesh.face(f);
    const Vec3 vertex = shape.mesh.positions[c[0]], middle = (shape.mesh.positions[c[0]] + shape.mesh.positions[c[1]]) * 0.5;
    for (const Vec3& at : {vertex, middle}) {
      if (shape.normal) {
        for (double side : {-1.0, 1.0}) points.push_back(at + shape.normal(at) * (side * offset));
      } else {
        for (int k = 0; k < 40; ++k) points.push_back(at + unit(Vec3{g(rng), g(rng), g(rng)}) * offset);
      }
    }
  }
  int undecided = 0;
  for (const Vec3& p : points) {
    std::size_t nearest = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t f = 0; f < shape.mesh.faceCount(); ++f) {
      const auto c = shape.mesh.face(f);
      const double d = norm(p - closestOnTriangle(p, shape.mesh.positions[c[0]], shape.mesh.positions[c[1]], shape.mesh.positions[c[2]]).point);
      if (d < best) best = d, nearest = f;
    }
    const std::optional<double> d = normals.signedDistance(p, nearest);
    if (!d) {
      ++undecided;
      continue;
    }
    EXPECT_NEAR(std::abs(*d), best, 1e-12);
    ASSERT_EQ(*d < 0, shape.distance(p) < 0) << "at (" << p.x << ", " << p.y << ", " << p.z << ")";
  }
  EXPECT_EQ(undecided, 0);
}

TEST(MeshSign, PseudoNormalsTellInsideFromOutsideEitherWayRound) {
  const double R = 1, r = 0.4;
  auto torusDistance = [=](const Vec3& p) { return std::hypot(std::hypot(p.x, p.y) - R, p.z) - r; };
  auto torusNormal = [=](const Vec3& p) {
    const double ring = std::hypot(p.x, p.y);
    return unit(Vec3{p.x * (ring - R) / ring, p.y * (ring - R) / ring, p.z});
  };
  const Mesh t = torus(R, r, 40, 20);
  // A chord of length h on a circle of radius rho sags h^2 / (8 rho): the smaller circle, the edges' longest.
  const double torusSag = std::pow(2 * kPi * (R + r) / 40, 2) / (8 * r);
  expectSignsOf({"torus", t, torusDistance, torusNormal}, torusSag);
  expectSignsOf({"torus inside out", reversed(t), torusDistance, torusNormal}, torusSag);

  auto shellDistance = [](const Vec3& p) { return std::max(norm(p) - 1.2, 0.6 - norm(p)); };
  auto shellNormal = [](const Vec3& p) { return norm(p) > 0.9 ? unit(p) : unit(p) * -1.0; };
  const Mesh outer = sphere(1.2, 36, 18), inner = sphere(0.6, 24, 12);
  const double shellSag = std::pow(2 * kPi * 1.2 / 36, 2) / (8 * 0.6);
  expectSignsOf({"shell, cavity as stored", merged(outer, inner), shellDistance, shellNormal}, shellSag);
  expectSignsOf({"shell, cavity reversed", merged(outer, reversed(inner)), shellDistance, shellNormal}, shellSag);

  // A spike: a tall, thin tetrahedron, whose edges meet at angles far sharper than a right angle.
  Mesh spike;
  spike.positions = {{-0.3, -0.2, -0.5}, {0.3, -0.2, -0.5}, {0, 0.3, -0.5}, {0.05, 0, 1.4}};
  for (const auto& face : {std::array<std::uint32_t, 3>{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}}) spike.addFace({face[0], face[1], face[2]});
  auto spikeDistance = [&](const Vec3& p) {  // the largest of the faces' plane distances: its sign is the spike's
    double d = -std::numeric_limits<double>::infinity();
    const Vec3 centre = (spike.positions[0] + spike.positions[1] + spike.positions[2] + spike.positions[3]) * 0.25;
    for (std::size_t f = 0; f < 4; ++f) {
      const auto c = spike.face(f);
      Vec3 n = unit(cross(spike.positions[c[1]] - spike.positions[c[0]], spike.positions[c[2]] - spike.positions[c[0]]));
      if (dot(n, centre - spike.positions[c[0]]) > 0) n = n * -1.0;
      d = std::max(d, dot(n, p - spike.positions[c[0]]));
    }
    return d;
  };
  expectSignsOf({"spike", spike, spikeDistance, nullptr}, 0);
  expectSignsOf({"spike inside out", reversed(spike), spikeDistance, nullptr}, 0);
}

// A mesh solid's query starts from its thread's last answer: asked in turn with another solid, and
// after long jumps, it gives what a fresh solid asked once gives, the side its mesh says.
TEST(MeshSign, MeshSolidsAskedInTurnAnswerAsAlone) {
  const Mesh t = torus(1, 0.4, 40, 20), s = sphere(0.7, 24, 12);
  const auto torusSolid = meshSolid(t, "torus"), sphereSolid = meshSolid(reversed(s), "sphere");
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.6, 1.6);
  for (int i = 0; i < 400; ++i) {
    const Vec3 p{u(rng), u(rng), u(rng) * 0.6};
    const double a = torusSolid->signedDistance(p), b = sphereSolid->signedDistance(p);
    EXPECT_NEAR(a, meshSolid(t, "torus")->signedDistance(p), 1e-12);
    EXPECT_NEAR(b, meshSolid(reversed(s), "sphere")->signedDistance(p), 1e-12);
    EXPECT_EQ(a < 0, insideByParity(t, p));
    EXPECT_EQ(b < 0, insideByParity(s, p));
  }
  // A walk in small steps, where each query starts from the last answer: the brute-force distance and
  // the mesh's own side.
  for (int i = 0; i < 600; ++i) {
    const Vec3 p{-1.6 + i * 0.0053, 0.3 * std::sin(i * 0.05), 0.25 * std::cos(i * 0.031)};
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t f = 0; f < t.faceCount(); ++f) {
      const auto c = t.face(f);
      best = std::min(best, norm(p - closestOnTriangle(p, t.positions[c[0]], t.positions[c[1]], t.positions[c[2]]).point));
    }
    const double d = torusSolid->signedDistance(p);
    EXPECT_NEAR(std::abs(d), best, 1e-12);
    EXPECT_EQ(d < 0, insideByParity(t, p));
  }
}

// Closed shells that overlap: the probes of one shell's faces disagree (some lie inside the other
// shell), so the pseudonormals are not used and the mesh's solid keeps the parity's side.
TEST(MeshSign, OverlappingShellsAreLeftToTheParity) {
  Mesh a = sphere(0.7, 24, 12), b = sphere(0.7, 24, 12);
  for (Vec3& p : b.positions) p.x += 0.5;
  const Mesh both = merged(a, b);
  EXPECT_FALSE(PseudoNormals(both, [&](const Vec3& p) { return insideByParity(both, p); }).usable());
  const auto solid = meshSolid(both, "two spheres");
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1, 1.5);
  for (int i = 0; i < 300; ++i) {
    const Vec3 p{u(rng), u(rng) * 0.8, u(rng) * 0.8};
    EXPECT_EQ(solid->signedDistance(p) < 0, insideByParity(both, p));
  }
}

}  // namespace
}  // namespace isoatlas::edit::dvt
