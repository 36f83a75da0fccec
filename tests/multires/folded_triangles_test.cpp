// Dense triangles drawn straight over the base domain: a dense mesh made by subdividing a base mesh
// has a known, fold-free parametrisation; moving one vertex past its ring folds exactly one triangle.
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "multires/folded_dense_triangles.h"
#include "tests/multires/mesh_shapes.h"

namespace isoatlas::multires {
namespace {

// Each base triangle cut into n x n triangles; dense vertex i has its lattice point's weights and
// sits off the base mesh (but for the base vertices).
Mesh subdivide(BaseMesh& base, int n) {
  Mesh dense;
  std::map<std::vector<std::pair<std::uint32_t, int>>, std::uint32_t> index;  // (base vertex, weight)
  for (std::uint32_t t = 0; t < base.triangleCount(); ++t) {
    const auto& c = base.triangles[t];
    auto vertex = [&](int i, int j) {  // weights (n - i - j, i, j) / n on the corners
      const int w[3] = {n - i - j, i, j};
      std::vector<std::pair<std::uint32_t, int>> key;
      for (int k = 0; k < 3; ++k)
        if (w[k] > 0) key.push_back({c[k], w[k]});
      std::sort(key.begin(), key.end());
      const auto [it, added] = index.insert({key, std::uint32_t(dense.positions.size())});
      if (added) {
        const std::array<double, 3> b{double(w[0]) / n, double(w[1]) / n, double(w[2]) / n};
        const double lift = 0.3 * (1 - *std::max_element(b.begin(), b.end()));  // 0 on base vertices
        dense.positions.push_back(base.pointAt(t, b) + Vec3{0.36, 0.48, 0.8} * lift);
        base.denseTriangle.push_back(t);
        base.denseBary.push_back(b);
        if (key.size() == 1) base.denseVertex[c[std::find(w, w + 3, n) - w]] = it->second;
      }
      return it->second;
    };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i + j < n; ++i) {
        dense.addFace({vertex(i, j), vertex(i + 1, j), vertex(i, j + 1)});
        if (i + j + 1 < n) dense.addFace({vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
      }
  }
  return dense;
}

BaseMesh octahedron() {
  BaseMesh base;
  base.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  base.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  base.denseVertex.assign(6, -1);
  return base;
}

BaseMesh openPyramid() {  // four triangles around an apex of valence 4, with a boundary
  BaseMesh base;
  base.positions = {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  base.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}};
  base.denseVertex.assign(5, -1);
  return base;
}

TEST(FoldedDenseTriangles, NoneOnASubdividedBaseMesh) {
  for (BaseMesh base : {octahedron(), openPyramid()}) {
    const Mesh dense = subdivide(base, 8);
    EXPECT_EQ(countFoldedTriangles(dense, base), 0u);
  }
}

// A mesh that is its own base (isoatlas build keeps small meshes whole): each dense vertex is a base
// vertex, placed in any one triangle around it, so a triangle's three corners can lie in three
// triangles that share no vertex. Over random placements (seeded), none folds.
TEST(FoldedDenseTriangles, NoneOnAMeshThatIsItsOwnBase) {
  std::mt19937 random(7);
  for (BaseMesh base : {octahedron(), openPyramid()}) {
    const Mesh dense = subdivide(base, 1);
    for (int trial = 0; trial < 50; ++trial) {
      for (std::size_t v = 0; v < dense.vertexCount(); ++v) {
        std::vector<std::pair<std::uint32_t, std::uint32_t>> around;  // (triangle, corner)
        for (std::uint32_t t = 0; t < base.triangleCount(); ++t)
          for (std::uint32_t k = 0; k < 3; ++k)
            if (base.denseVertex[base.triangles[t][k]] == std::int64_t(v)) around.push_back({t, k});
        ASSERT_FALSE(around.empty());
        const auto [t, k] = around[std::uniform_int_distribution<std::size_t>(0, around.size() - 1)(random)];
        base.denseTriangle[v] = t;
        base.denseBary[v] = {0, 0, 0};
        base.denseBary[v][k] = 1;
      }
      ASSERT_EQ(countFoldedTriangles(dense, base), 0u) << "trial " << trial;
    }
  }
}

// Folds counted by hand: in base triangle t cut 6 x 6, the centroid's dense vertex (lattice (2, 2))
// is pushed to lattice (2.6, 2.6), past the line i + j = 5 through its neighbours (3, 2) and (2, 3).
// Of its six triangles exactly one turns over: ((2,2), (3,2), (2,3)); the other five keep their
// orientation (each checked by hand: their signed areas stay 0.4 to 2.2).
void pushCentrePastItsRing(const Mesh& dense, BaseMesh& base, std::uint32_t t) {
  for (std::size_t v = 0; v < dense.vertexCount(); ++v) {
    const auto& b = base.denseBary[v];
    if (base.denseTriangle[v] == t && std::abs(b[0] - 1.0 / 3) < 1e-12 && std::abs(b[1] - 1.0 / 3) < 1e-12) {
      base.denseBary[v] = {0.8 / 6, 2.6 / 6, 2.6 / 6};
      return;
    }
  }
  FAIL() << "no centroid vertex in base triangle " << t;
}

TEST(FoldedDenseTriangles, CountedByHand) {
  BaseMesh base = octahedron();
  const Mesh dense = subdivide(base, 6);
  pushCentrePastItsRing(dense, base, 0);
  EXPECT_EQ(countFoldedTriangles(dense, base), 1u);
  pushCentrePastItsRing(dense, base, 5);
  EXPECT_EQ(countFoldedTriangles(dense, base), 2u);
}

}  // namespace
}  // namespace isoatlas::multires
