#include "core/distance/mesh_distance.h"

#include <CGAL/boost/graph/property_maps.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/point_generators_3.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "core/distance/morton_order.h"
#include "core/distance/triangle_tree.h"
#include "core/error.h"

namespace isoatlas {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

using Point = Kernel::Point_3;

Vec3 vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

// Refuses what CGAL cannot measure: no faces, faces of other than three corners, a point that is
// not finite (CGAL's face sampler never returns on a non-finite area), or only faces that name a
// vertex twice or lie on a line (they cover nothing; the sampler, CGAL's too, would never return).
void requireMeasurable(const Mesh& mesh, const char* which) {
  const std::string the = std::string("Hausdorff distance: the ") + which + " mesh";
  require(mesh.faceCount() > 0 && mesh.allFacesHave(3), the + " must be a non-empty triangle mesh");
  for (const Vec3& p : mesh.positions)
    require(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z), the + " has a vertex that is not a finite point");
  // A face with area to draw points from (with none, the sampler's draw by area finds no face).
  bool covers = false;
  for (std::size_t f = 0; f < mesh.faceCount() && !covers; ++f) {
    const auto c = mesh.face(f);
    const Vec3 n = cross(mesh.positions[c[1]] - mesh.positions[c[0]], mesh.positions[c[2]] - mesh.positions[c[0]]);
    covers = namesThreeVertices(c) && dot(n, n) > 0;
  }
  require(covers, std::string("Hausdorff distance: every face of the ") + which + " mesh is degenerate (no area)");
}

// A soup's samples as CGAL's sample_triangle_soup draws them for approximate_Hausdorff_distance, bit
// for bit: the vertices, then `facePoints` points, each in a face drawn by area (CGAL's area, running
// sum and generators, seeded 0, called in the same order). Only the faces' areas, the long part on a
// fine mesh, are computed in parallel; the running sum and the draws stay in order.
std::vector<Point> soupSamples(const Mesh& mesh, std::size_t facePoints) {
  std::vector<Point> out;
  out.reserve(mesh.vertexCount() + facePoints);
  for (const Vec3& p : mesh.positions) out.emplace_back(p.x, p.y, p.z);
  const auto corner = [&](std::size_t f, int k) { return out[mesh.face(f)[k]]; };
  std::vector<double> runningArea(mesh.faceCount());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.faceCount()), [&](const tbb::blocked_range<std::size_t>& r) {
    const auto squaredArea = Kernel().compute_squared_area_3_object();
    for (std::size_t f = r.begin(); f != r.end(); ++f)
      runningArea[f] = CGAL::to_double(CGAL::approximate_sqrt(squaredArea(corner(f, 0), corner(f, 1), corner(f, 2))));
  });
  double total = 0;
  for (double& a : runningArea) a = total += a;
  CGAL::Random chooseFace(0), inFace(0);  // CGAL draws the face with the seed, the point with its default generator
  for (std::size_t k = 0; k < facePoints; ++k) {
    const std::size_t f = std::upper_bound(runningArea.begin(), runningArea.end(), chooseFace.get_double(0, total)) - runningArea.begin();
    out.push_back(*CGAL::Random_points_in_triangle_3<Point>(corner(f, 0), corner(f, 1), corner(f, 2), inFace));
  }
  return out;
}

// The samples of a mesh that is not an oriented manifold, by CGAL's own sampler on a Surface_mesh: the
// faces it refuses go in as a soup of their own vertices, so every triangle is still sampled. (On an
// oriented manifold, Surface_mesh takes every face, and its samples are the soup's bit for bit: both
// read a face's corners from its first, weigh faces by the same area and draw alike.)
std::vector<Point> halfedgeSamples(const Mesh& mesh, std::size_t facePoints) {
  std::vector<Point> points;
  points.reserve(mesh.vertexCount());
  for (const Vec3& p : mesh.positions) points.emplace_back(p.x, p.y, p.z);
  SurfaceMesh sm;
  sm.reserve(SurfaceMesh::size_type(mesh.vertexCount()), 0, SurfaceMesh::size_type(mesh.faceCount()));
  for (const Point& p : points) sm.add_vertex(p);
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto c = mesh.face(f);
    const SurfaceMesh::Vertex_index v[3] = {SurfaceMesh::Vertex_index(c[0]), SurfaceMesh::Vertex_index(c[1]),
                                            SurfaceMesh::Vertex_index(c[2])};
    if (sm.add_face(v[0], v[1], v[2]) != SurfaceMesh::null_face()) continue;
    if (!namesThreeVertices(c)) continue;
    // From our own copy of the points: a reference into the mesh's would dangle once it grows.
    const auto a = sm.add_vertex(points[c[0]]), b = sm.add_vertex(points[c[1]]), d = sm.add_vertex(points[c[2]]);
    sm.add_face(a, b, d);
  }
  // CGAL 5.5 places the points inside each chosen face with its default generator, whatever the seed
  // given: seeded here too, so that a figure repeats.
  CGAL::get_default_random() = CGAL::Random(0);
  std::vector<Point> out;
  out.reserve(sm.number_of_vertices() + facePoints);
  PMP::sample_triangle_mesh(
      sm, std::back_inserter(out),
      CGAL::parameters::number_of_points_on_faces(facePoints).do_sample_edges(false).do_sample_vertices(true).random_seed(0));
  return out;
}

// A mesh's samples as CGAL's approximate_Hausdorff_distance draws them, in Morton order: each query's
// hint, the last answer, is then near. (CGAL's max_distance_to_triangle_mesh queries them in Hilbert
// order, for the same reason, at several times the cost of sorting: the order decides no largest
// distance, and the RMS only in its last digits, by the order of the sum.) Drawn from the soup of
// triangles where the mesh is an oriented manifold, else through halfedges.
std::vector<Point> samplesOf(const Mesh& mesh, std::size_t facePoints, bool orientedManifold) {
  const std::vector<Point> drawn = orientedManifold ? soupSamples(mesh, facePoints) : halfedgeSamples(mesh, facePoints);
  const std::vector<std::uint64_t> keys = mortonOrder(drawn.size(), [&](std::size_t i) { return vec(drawn[i]); });
  std::vector<Point> out(keys.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, keys.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) out[i] = drawn[mortonIndex(keys[i])];
  });
  return out;
}

// The farthest and the mean squared distance of the samples from the tree's surface, by CGAL's
// closest-point projections (as max_distance_to_triangle_mesh makes them), each query hinted by the
// last answer.
struct OneWay {
  double largest = 0, rms = 0;
};
OneWay distances(const std::vector<Point>& samples, const TriangleTree& tree) {
  // Each sample's squared distance in its own slot, summed in order afterwards: the same figure
  // whatever the threads did.
  std::vector<double> d2(samples.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples.size()), [&](const tbb::blocked_range<std::size_t>& range) {
    TriangleTree::Closest hint = tree.closest(vec(samples[range.begin()]));
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const Point& p = samples[i];
      hint = tree.closest(vec(p), hint);
      d2[i] = CGAL::squared_distance(Point(hint.point.x, hint.point.y, hint.point.z), p);
    }
  });
  double largest2 = 0, sum2 = 0;
  for (const double x : d2) largest2 = std::max(largest2, x), sum2 += x;
  return {std::sqrt(largest2), d2.empty() ? 0 : std::sqrt(sum2 / double(d2.size()))};
}

}  // namespace

struct MeshDistances::State {
  std::vector<Point> samples;  // in Morton order
  std::size_t facePoints;
  std::optional<TriangleTree> tree;
};

MeshDistances::MeshDistances(const Mesh& a, std::size_t facePoints) : state_(std::make_unique<State>()) {
  requireMeasurable(a, "first");
  // Sampled as an oriented manifold while its topology is analysed (see to()).
  MeshTopology topology;
  tbb::parallel_invoke([&] { state_->samples = samplesOf(a, facePoints, true); }, [&] { topology = analyzeTopology(a); },
                       [&] { state_->tree.emplace(a); });
  if (!(topology.manifold && topology.oriented)) state_->samples = samplesOf(a, facePoints, false);
  state_->facePoints = facePoints;
}

MeshDistances::~MeshDistances() = default;

// Three parts side by side: b's tree is built and a's samples measured against it; b is sampled and
// measured against a's tree; b's topology is analysed. b is sampled as an oriented manifold (as every
// level of a model is) before its topology says so, and sampled again if it is not one.
Hausdorff MeshDistances::to(const Mesh& b, MeshTopology* topologyOfB) const {
  requireMeasurable(b, "second");
  OneWay aToB, bToA;
  MeshTopology topology;
  tbb::parallel_invoke(
      [&] {
        const TriangleTree tree(b);
        aToB = distances(state_->samples, tree);
      },
      [&] { bToA = distances(samplesOf(b, state_->facePoints, true), *state_->tree); }, [&] { topology = analyzeTopology(b); });
  if (!(topology.manifold && topology.oriented)) bToA = distances(samplesOf(b, state_->facePoints, false), *state_->tree);
  if (topologyOfB) *topologyOfB = std::move(topology);
  return {aToB.largest, bToA.largest, aToB.rms, bToA.rms};
}

Hausdorff hausdorffDistance(const Mesh& a, const Mesh& b, std::size_t facePoints) { return MeshDistances(a, facePoints).to(b); }

double psnrDb(double diagonal, double distance) {
  return distance > 0 ? 20 * std::log10(diagonal / distance) : std::numeric_limits<double>::infinity();
}

}  // namespace isoatlas
