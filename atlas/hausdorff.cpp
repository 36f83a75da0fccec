#include "atlas/hausdorff.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/boost/graph/property_maps.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/spatial_sort.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

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

using Point = Kernel::Point_3;
using Triangles = std::vector<Kernel::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

// The mesh's triangles by value, each with its corners in the order CGAL's face-graph primitive
// reads them: a tree over them answers as a tree over the mesh would, without walking the
// halfedges at every box it builds or triangle it measures.
Triangles trianglesOf(const SurfaceMesh& mesh) {
  const CGAL::Triangle_from_face_descriptor_map<SurfaceMesh, SurfaceMesh::Property_map<SurfaceMesh::Vertex_index, Point>> corners(
      &mesh, mesh.points());
  Triangles out;
  out.reserve(mesh.number_of_faces());
  for (const auto f : faces(mesh)) out.push_back(get(corners, f));
  return out;
}

// Every query here is given a hint (the last answer), so CGAL's search tree of hints, which it
// would build over one point per triangle, is never wanted.
void buildTree(Tree& tree, const Triangles& triangles) {
  tree.do_not_accelerate_distance_queries();
  tree.rebuild(triangles.begin(), triangles.end());
}

// A mesh's samples as CGAL's approximate_Hausdorff_distance draws them: its vertices plus
// `facePoints` random face points. CGAL 5.5 places the points inside each chosen face with its
// default generator, whatever the seed given: seeded here too, so that a figure repeats.
std::vector<Point> samplePoints(const SurfaceMesh& mesh, std::size_t facePoints) {
  CGAL::get_default_random() = CGAL::Random(0);
  std::vector<Point> points;
  PMP::sample_triangle_mesh(mesh, std::back_inserter(points),
                            CGAL::parameters::number_of_points_on_faces(facePoints).do_sample_edges(false).do_sample_vertices(true).random_seed(0));
  return points;
}

// The farthest and the mean squared distance of the points from the tree's surface, by CGAL's
// closest-point queries (as max_distance_to_triangle_mesh makes them: points in spatial order, each
// query hinted by the last answer).
struct OneWay {
  double largest = 0, rms = 0;
};
OneWay distances(std::vector<Point> points, const Tree& tree, const Point& start) {
  CGAL::spatial_sort(points.begin(), points.end());
  // Each point's squared distance in its own slot, summed in order afterwards: the same figure
  // whatever the threads did.
  std::vector<double> d2(points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size()), [&](const tbb::blocked_range<std::size_t>& range) {
    Point hint = start;
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      hint = tree.closest_point(points[i], hint);
      d2[i] = CGAL::squared_distance(hint, points[i]);
    }
  });
  double largest2 = 0, sum2 = 0;
  for (const double x : d2) largest2 = std::max(largest2, x), sum2 += x;
  return {std::sqrt(largest2), d2.empty() ? 0 : std::sqrt(sum2 / double(d2.size()))};
}

}  // namespace

struct MeshDistances::State {
  std::vector<Point> samples;
  std::size_t facePoints;
  Triangles triangles;
  Tree tree;
  Point firstVertex;  // the first hint of queries into the tree
};

MeshDistances::MeshDistances(const Mesh& a, std::size_t facePoints) : state_(std::make_unique<State>()) {
  const SurfaceMesh mesh = toSurfaceMesh(a, "first");  // for CGAL's sampler; the tree keeps triangles
  state_->samples = samplePoints(mesh, facePoints);
  state_->facePoints = facePoints;
  state_->triangles = trianglesOf(mesh);
  state_->firstVertex = mesh.point(*vertices(mesh).first);
  buildTree(state_->tree, state_->triangles);
}

MeshDistances::~MeshDistances() = default;

// The two ways apart: building b's tree takes one core, so b's samples are drawn and measured
// against a's tree beside it.
Hausdorff MeshDistances::to(const Mesh& b) const {
  const SurfaceMesh mb = toSurfaceMesh(b, "second");
  OneWay aToB, bToA;
  tbb::parallel_invoke(
      [&] {
        const Triangles triangles = trianglesOf(mb);
        Tree tree;
        buildTree(tree, triangles);
        aToB = distances(state_->samples, tree, mb.point(*vertices(mb).first));
      },
      [&] {
        bToA = distances(samplePoints(mb, state_->facePoints), state_->tree, state_->firstVertex);
      });
  return {aToB.largest, bToA.largest, aToB.rms, bToA.rms};
}

Hausdorff hausdorffDistance(const Mesh& a, const Mesh& b, std::size_t facePoints) { return MeshDistances(a, facePoints).to(b); }

double psnrDb(double diagonal, double distance) {
  return distance > 0 ? 20 * std::log10(diagonal / distance) : std::numeric_limits<double>::infinity();
}

}  // namespace isoatlas::atlas
