// The one file of levelset/dvt with CGAL's headers.
#include "levelset/solids/mesh_solid.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <atomic>
#include <cmath>
#include <optional>
#include <vector>

#include "core/error.h"
#include "core/mesh_topology.h"
#include "levelset/solids/mesh_sign.h"

namespace isoatlas::levelset::dvt {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

class MeshDistance final : public DistanceSolid {
public:
  MeshDistance(const Mesh& mesh, bool oriented) {
    triangles_.reserve(mesh.faceCount());
    auto point = [&](std::uint32_t v) {
      const Vec3& p = mesh.positions[v];
      return Kernel::Point_3(p.x, p.y, p.z);
    };
    for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
      const auto c = mesh.face(f);
      triangles_.emplace_back(point(c[0]), point(c[1]), point(c[2]));
    }
    for (const Triangle& t : triangles_) meanEdge_ += std::sqrt(CGAL::squared_distance(t[0], t[1])) / double(triangles_.size());
    tree_.insert(triangles_.begin(), triangles_.end());
    tree_.accelerate_distance_queries();
    if (oriented) {
      pseudoNormals_.emplace(mesh, [&](const Vec3& p) { return byParity(p, 1) < 0; });
      if (!pseudoNormals_->usable()) pseudoNormals_.reset();
    }
  }

  double signedDistance(const Vec3& p) const override {
    const Kernel::Point_3 q(p.x, p.y, p.z);
    if (!pseudoNormals_) return byParity(p, std::sqrt(tree_.squared_distance(q)));
    const auto [closest, triangle] = closestTo(q);
    if (const auto d = pseudoNormals_->signedDistance(p, std::size_t(triangle - triangles_.begin()))) return *d;
    return byParity(p, std::sqrt(CGAL::squared_distance(q, closest)));  // the normal could not tell
  }

private:
  // The closest point to q. The rasteriser asks of neighbouring cells in turn, so the last answer on
  // this thread bounds the search well when q is near the last query (its distance exceeds the true
  // one by at most twice the step): about as well as CGAL's own hint (the nearest vertex, within an
  // edge of the surface) when the step is under the last distance plus a mean edge, and without
  // searching for it. After a longer step, CGAL's hint.
  Tree::Point_and_primitive_id closestTo(const Kernel::Point_3& q) const {
    struct Last {
      std::uint64_t solid = 0;
      Kernel::Point_3 query;
      double distance = 0;
      Tree::Point_and_primitive_id closest;
    };
    thread_local Last last;
    const bool near = last.solid == id_ && std::sqrt(CGAL::squared_distance(q, last.query)) < last.distance + meanEdge_;
    last.closest = near ? tree_.closest_point_and_primitive(q, last.closest) : tree_.closest_point_and_primitive(q);
    last.solid = id_, last.query = q, last.distance = std::sqrt(CGAL::squared_distance(q, last.closest.first));
    return last.closest;
  }

  // `distance`, negative where a ray from p crosses the mesh an odd number of times.
  double byParity(const Vec3& p, double distance) const {
    // A direction no mesh of ours is aligned with, so the ray meets edges and vertices almost never.
    const Kernel::Ray_3 ray(Kernel::Point_3(p.x, p.y, p.z), Kernel::Vector_3(0.5773, 0.5802, 0.5743));
    return tree_.number_of_intersected_primitives(ray) % 2 == 1 ? -distance : distance;
  }

  std::vector<Triangle> triangles_;
  Tree tree_;
  std::optional<PseudoNormals> pseudoNormals_;  // the side without a ray, where the mesh is oriented
  double meanEdge_ = 0;
  // Tells this solid's hint from another's (an address can be reused by a later solid).
  static inline std::atomic<std::uint64_t> solids_{0};
  const std::uint64_t id_ = ++solids_;
};

}  // namespace

std::unique_ptr<DistanceSolid> meshSolid(const Mesh& mesh, const std::string& name) {
  require(mesh.faceCount() > 0 && mesh.allFacesHave(3), name + ": a mesh to voxelise must be triangles");
  const MeshTopology t = analyzeTopology(mesh);
  require(t.closed, name + ": the mesh is not closed (a solid needs a closed surface)");
  return std::make_unique<MeshDistance>(mesh, t.oriented);
}

}  // namespace isoatlas::levelset::dvt
