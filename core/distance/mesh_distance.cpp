#include "core/distance/mesh_distance.h"

#include <CGAL/boost/graph/property_maps.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/spatial_sort.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "core/distance/triangle_tree.h"
#include "core/error.h"

namespace isoatlas {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

using Point = Kernel::Point_3;

// Refuses what CGAL cannot measure: no faces, faces of other than three corners, a point that is
// not finite (CGAL's face sampler never returns on a non-finite area), or only faces that name a
// vertex twice (they cover nothing).
void requireMeasurable(const Mesh& mesh, const char* which) {
  const std::string the = std::string("Hausdorff distance: the ") + which + " mesh";
  require(mesh.faceCount() > 0 && mesh.allFacesHave(3), the + " must be a non-empty triangle mesh");
  for (const Vec3& p : mesh.positions)
    require(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z), the + " has a vertex that is not a finite point");
  bool covers = false;
  for (std::size_t f = 0; f < mesh.faceCount() && !covers; ++f) covers = namesThreeVertices(mesh.face(f));
  require(covers, std::string("Hausdorff distance: every face of the ") + which + " mesh is degenerate");
}

// A mesh as CGAL's sampler reads it. Where Surface_mesh would take every face (an oriented
// manifold), the positions and corner triples go to CGAL's soup sampler as they are: its samples
// are then the Surface_mesh sampler's bit for bit (both read a face's corners from its first, weigh
// faces by the same area and draw alike), without building the halfedges. Elsewhere a Surface_mesh
// is built, and the faces it refuses go in as a soup of their own vertices, so every triangle is
// still sampled.
struct SampledSurface {
  std::vector<Point> points;
  std::vector<std::array<std::size_t, 3>> corners;  // the soup's faces, when no halfedges are wanted
  std::optional<SurfaceMesh> halfedges;
};

SampledSurface sampledSurface(const Mesh& mesh, const MeshTopology& topology) {
  SampledSurface out;
  out.points.reserve(mesh.vertexCount());
  for (const Vec3& p : mesh.positions) out.points.emplace_back(p.x, p.y, p.z);
  if (topology.manifold && topology.oriented) {
    out.corners.reserve(mesh.faceCount());
    for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
      const auto c = mesh.face(f);
      out.corners.push_back({c[0], c[1], c[2]});
    }
    return out;
  }
  SurfaceMesh& sm = out.halfedges.emplace();
  sm.reserve(SurfaceMesh::size_type(mesh.vertexCount()), 0, SurfaceMesh::size_type(mesh.faceCount()));
  for (const Point& p : out.points) sm.add_vertex(p);
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto c = mesh.face(f);
    const SurfaceMesh::Vertex_index v[3] = {SurfaceMesh::Vertex_index(c[0]), SurfaceMesh::Vertex_index(c[1]),
                                            SurfaceMesh::Vertex_index(c[2])};
    if (sm.add_face(v[0], v[1], v[2]) != SurfaceMesh::null_face()) continue;
    if (!namesThreeVertices(c)) continue;
    // From our own copy of the points: a reference into the mesh's would dangle once it grows.
    const auto a = sm.add_vertex(out.points[c[0]]), b = sm.add_vertex(out.points[c[1]]), d = sm.add_vertex(out.points[c[2]]);
    sm.add_face(a, b, d);
  }
  return out;
}

// The first hint of queries into a mesh's tree: its first vertex, as CGAL's own distance takes it.
Vec3 firstVertex(const Mesh& mesh) { return mesh.positions[0]; }

// A surface's samples as CGAL's approximate_Hausdorff_distance draws them: its vertices plus
// `facePoints` random face points. CGAL 5.5 places the points inside each chosen face with its
// default generator, whatever the seed given: seeded here too, so that a figure repeats.
std::vector<Point> samplePoints(const SampledSurface& surface, std::size_t facePoints) {
  CGAL::get_default_random() = CGAL::Random(0);
  std::vector<Point> points;
  const auto parameters =
      CGAL::parameters::number_of_points_on_faces(facePoints).do_sample_edges(false).do_sample_vertices(true).random_seed(0);
  if (surface.halfedges) PMP::sample_triangle_mesh(*surface.halfedges, std::back_inserter(points), parameters);
  else PMP::sample_triangle_soup(surface.points, surface.corners, std::back_inserter(points), parameters);
  return points;
}

// The farthest and the mean squared distance of the points from the tree's surface, by CGAL's
// closest-point queries (as max_distance_to_triangle_mesh makes them: points in spatial order, each
// query hinted by the last answer).
struct OneWay {
  double largest = 0, rms = 0;
};
OneWay distances(std::vector<Point> points, const TriangleTree& tree, const Vec3& start) {
  CGAL::spatial_sort(points.begin(), points.end());
  // Each point's squared distance in its own slot, summed in order afterwards: the same figure
  // whatever the threads did.
  std::vector<double> d2(points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size()), [&](const tbb::blocked_range<std::size_t>& range) {
    Vec3 hint = start;
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const Point& p = points[i];
      hint = tree.closestPoint({p.x(), p.y(), p.z()}, hint);
      d2[i] = CGAL::squared_distance(Point(hint.x, hint.y, hint.z), p);
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
  std::optional<TriangleTree> tree;
  Vec3 firstVertex;  // the first hint of queries into the tree
};

MeshDistances::MeshDistances(const Mesh& a, std::size_t facePoints) : state_(std::make_unique<State>()) {
  requireMeasurable(a, "first");
  state_->samples = samplePoints(sampledSurface(a, analyzeTopology(a)), facePoints);
  state_->facePoints = facePoints;
  state_->tree.emplace(a, TriangleTree::Hints::Given);
  state_->firstVertex = firstVertex(a);
}

MeshDistances::~MeshDistances() = default;

// The two ways apart: building b's tree takes one core, so b's topology (whether its samples may be
// drawn from a soup) and samples are made and measured against a's tree beside it.
Hausdorff MeshDistances::to(const Mesh& b, MeshTopology* topologyOfB) const {
  requireMeasurable(b, "second");
  OneWay aToB, bToA;
  MeshTopology topology;
  tbb::parallel_invoke(
      [&] {
        const TriangleTree tree(b, TriangleTree::Hints::Given);
        aToB = distances(state_->samples, tree, firstVertex(b));
      },
      [&] {
        topology = analyzeTopology(b);
        bToA = distances(samplePoints(sampledSurface(b, topology), state_->facePoints), *state_->tree, state_->firstVertex);
      });
  if (topologyOfB) *topologyOfB = std::move(topology);
  return {aToB.largest, bToA.largest, aToB.rms, bToA.rms};
}

Hausdorff hausdorffDistance(const Mesh& a, const Mesh& b, std::size_t facePoints) { return MeshDistances(a, facePoints).to(b); }

double psnrDb(double diagonal, double distance) {
  return distance > 0 ? 20 * std::log10(diagonal / distance) : std::numeric_limits<double>::infinity();
}

}  // namespace isoatlas
