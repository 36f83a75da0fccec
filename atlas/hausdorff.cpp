#include "atlas/hausdorff.h"

#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <limits>

#include "core/error.h"

namespace isoatlas::atlas {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

SurfaceMesh toSurfaceMesh(const Mesh& mesh, const char* which) {
  require(mesh.faceCount() > 0 && mesh.allFacesHave(3), std::string("Hausdorff distance: the ") + which +
                                                             " mesh must be a non-empty triangle mesh");
  // CGAL's face sampler never returns on a non-finite area.
  for (const Vec3& p : mesh.positions)
    require(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z),
            std::string("Hausdorff distance: the ") + which + " mesh has a vertex that is not a finite point");
  SurfaceMesh out;
  out.reserve(SurfaceMesh::size_type(mesh.vertexCount()), 0, SurfaceMesh::size_type(mesh.faceCount()));
  for (const Vec3& p : mesh.positions) out.add_vertex({p.x, p.y, p.z});
  // Surface_mesh takes only what forms a manifold: faces it refuses go in as a soup of their own
  // vertices, so every triangle is still measured.
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto c = mesh.face(f);
    const SurfaceMesh::Vertex_index v[3] = {SurfaceMesh::Vertex_index(c[0]), SurfaceMesh::Vertex_index(c[1]),
                                            SurfaceMesh::Vertex_index(c[2])};
    if (out.add_face(v[0], v[1], v[2]) != SurfaceMesh::null_face()) continue;
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;  // a degenerate face covers nothing
    const auto a = out.add_vertex(out.point(v[0])), b = out.add_vertex(out.point(v[1])), d = out.add_vertex(out.point(v[2]));
    out.add_face(a, b, d);
  }
  require(out.number_of_faces() > 0, std::string("Hausdorff distance: every face of the ") + which + " mesh is degenerate");
  return out;
}

double oneWay(const SurfaceMesh& from, const SurfaceMesh& to, std::size_t facePoints) {
  // CGAL 5.5 places the points inside each chosen face with its default generator, whatever the
  // seed given: seeded here too, so that a figure repeats.
  CGAL::get_default_random() = CGAL::Random(0);
  return PMP::approximate_Hausdorff_distance<CGAL::Parallel_if_available_tag>(
      from, to,
      CGAL::parameters::number_of_points_on_faces(facePoints).do_sample_edges(false).do_sample_vertices(true).random_seed(0));
}

}  // namespace

Hausdorff hausdorffDistance(const Mesh& a, const Mesh& b, std::size_t facePoints) {
  const SurfaceMesh ma = toSurfaceMesh(a, "first"), mb = toSurfaceMesh(b, "second");
  return {oneWay(ma, mb, facePoints), oneWay(mb, ma, facePoints)};
}

double psnrDb(double diagonal, double distance) {
  return distance > 0 ? 20 * std::log10(diagonal / distance) : std::numeric_limits<double>::infinity();
}

}  // namespace isoatlas::atlas
