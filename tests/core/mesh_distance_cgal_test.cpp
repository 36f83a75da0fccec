// MeshDistances against CGAL's own one call: Polygon_mesh_processing's
// approximate_Hausdorff_distance, seeded as mesh_distance.cpp seeds it, gives the same figures bit for
// bit both ways (the yardstick every reported PSNR rests on). The one test file with CGAL's headers.
#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <random>

#include "core/distance/mesh_distance.h"
#include "core/mesh_topology.h"
#include "tests/multires/mesh_shapes.h"

namespace isoatlas {
namespace {

using SurfaceMesh = CGAL::Surface_mesh<CGAL::Simple_cartesian<double>::Point_3>;

SurfaceMesh surfaceMesh(const Mesh& mesh) {
  SurfaceMesh out;
  for (const Vec3& p : mesh.positions) out.add_vertex({p.x, p.y, p.z});
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto c = mesh.face(f);
    out.add_face(SurfaceMesh::Vertex_index(c[0]), SurfaceMesh::Vertex_index(c[1]), SurfaceMesh::Vertex_index(c[2]));
  }
  return out;
}

double cgalOneWay(const SurfaceMesh& from, const SurfaceMesh& to, std::size_t facePoints) {
  CGAL::get_default_random() = CGAL::Random(0);
  return CGAL::Polygon_mesh_processing::approximate_Hausdorff_distance<CGAL::Parallel_if_available_tag>(
      from, to,
      CGAL::parameters::number_of_points_on_faces(facePoints).do_sample_edges(false).do_sample_vertices(true).random_seed(0));
}

TEST(MeshDistances, AnswersAsCgalsApproximateHausdorffDistance) {
  const Mesh a = test::sphereMesh(10), b = test::torusMesh(40, 20, 8, 3);
  const SurfaceMesh sa = surfaceMesh(a), sb = surfaceMesh(b);
  const MeshDistances fromA(a, 3000);
  const Hausdorff h = fromA.to(b);
  EXPECT_EQ(h.aToB, cgalOneWay(sa, sb, 3000));
  EXPECT_EQ(h.bToA, cgalOneWay(sb, sa, 3000));
  EXPECT_GT(h.aToB, 1.0);
}

// An oriented manifold is sampled as a soup of triangles, without building its halfedges: the same
// samples as CGAL's own sampler on the Surface_mesh, whatever order the faces come in and whichever
// corner each starts from (Surface_mesh takes every face of an oriented manifold in any order).
TEST(MeshDistances, ASoupOfAnOrientedManifoldAnswersAsItsSurfaceMesh) {
  // b: a coarse torus, whose farthest points from the fine one lie inside its faces, where the
  // random face points (not its vertices) find them.
  const Mesh a = test::torusMesh(80, 40, 8, 3), coarse = test::torusMesh(12, 6, 8, 3);
  std::vector<std::array<std::uint32_t, 3>> faces;
  for (std::size_t f = 0; f < coarse.faceCount(); ++f) {
    const auto c = coarse.face(f);
    faces.push_back({c[f % 3], c[(f + 1) % 3], c[(f + 2) % 3]});  // the same face, from another corner
  }
  std::shuffle(faces.begin(), faces.end(), std::mt19937(7));
  Mesh b;
  b.positions = coarse.positions;
  for (const auto& c : faces) b.addFace({c[0], c[1], c[2]});
  const MeshTopology topology = analyzeTopology(b);
  ASSERT_TRUE(topology.manifold && topology.oriented);
  const SurfaceMesh sa = surfaceMesh(a), sb = surfaceMesh(b);
  ASSERT_EQ(sb.number_of_faces(), b.faceCount());
  MeshTopology reported;
  const Hausdorff h = MeshDistances(a, 3000).to(b, &reported);
  EXPECT_EQ(h.aToB, cgalOneWay(sa, sb, 3000));
  EXPECT_EQ(h.bToA, cgalOneWay(sb, sa, 3000));
  EXPECT_EQ(reported.genus, topology.genus);
  EXPECT_TRUE(reported.oriented);
}

}  // namespace
}  // namespace isoatlas
