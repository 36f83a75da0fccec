// atlas::MeshDistances against CGAL's own one call: Polygon_mesh_processing's
// approximate_Hausdorff_distance, seeded as hausdorff.cpp seeds it, gives the same figures bit for
// bit both ways (the yardstick every reported PSNR rests on). The one test file with CGAL's headers.
#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include "atlas/hausdorff.h"
#include "tests/multires/mesh_shapes.h"

namespace isoatlas::atlas {
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

}  // namespace
}  // namespace isoatlas::atlas
