#include "atlas/hausdorff.h"

#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_triangle_primitive.h>

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

struct NearestPoints::Tree {
  using Triangle = Kernel::Triangle_3;
  using Iterator = std::vector<Triangle>::const_iterator;
  using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;
  using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  std::vector<Triangle> triangles;
  AabbTree tree;
};

NearestPoints::NearestPoints(const Mesh& mesh) : mesh_(mesh), tree_(std::make_unique<Tree>()) {
  require(mesh.faceCount() > 0 && mesh.allFacesHave(3), "nearest points: the mesh must be a non-empty triangle mesh");
  auto point = [&](std::uint32_t v) { return Kernel::Point_3(mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z); };
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto c = mesh.face(f);
    tree_->triangles.emplace_back(point(c[0]), point(c[1]), point(c[2]));
  }
  tree_->tree.insert(tree_->triangles.cbegin(), tree_->triangles.cend());
  tree_->tree.accelerate_distance_queries();
}

NearestPoints::~NearestPoints() = default;

NearestPoints::Hit NearestPoints::nearest(const Vec3& query) const {
  const auto [p, primitive] = tree_->tree.closest_point_and_primitive(Kernel::Point_3(query.x, query.y, query.z));
  const std::uint32_t face = std::uint32_t(primitive - tree_->triangles.cbegin());
  const auto c = mesh_.face(face);
  const Vec3 a = mesh_.positions[c[0]], b = mesh_.positions[c[1]], d = mesh_.positions[c[2]], x{p.x(), p.y(), p.z()};
  // Barycentric weights of x on (a, b, d), by areas (x lies on the triangle).
  const Vec3 n = cross(b - a, d - a);
  const double area = dot(n, n);
  std::array<double, 3> w{1.0 / 3, 1.0 / 3, 1.0 / 3};
  if (area > 0) {
    w[1] = dot(cross(x - a, d - a), n) / area;
    w[2] = dot(cross(b - a, x - a), n) / area;
    w[0] = 1 - w[1] - w[2];
  }
  return {face, w, x};
}

double psnrDb(double diagonal, double distance) {
  return distance > 0 ? 20 * std::log10(diagonal / distance) : std::numeric_limits<double>::infinity();
}

}  // namespace isoatlas::atlas
