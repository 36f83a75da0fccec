#include "edit/solids/mesh_solid.h"

#include <atomic>
#include <cmath>
#include <optional>

#include "core/distance/triangle_tree.h"
#include "core/error.h"
#include "core/mesh_topology.h"
#include "edit/solids/mesh_sign.h"

namespace isoatlas::edit::dvt {
namespace {

class MeshDistance final : public DistanceSolid {
public:
  MeshDistance(const Mesh& mesh, bool oriented) : tree_(mesh) {
    for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
      const auto c = mesh.face(f);
      meanEdge_ += norm(mesh.positions[c[1]] - mesh.positions[c[0]]) / double(mesh.faceCount());
    }
    if (oriented) {
      pseudoNormals_.emplace(mesh, [&](const Vec3& p) { return byParity(p, 1) < 0; });
      if (!pseudoNormals_->usable()) pseudoNormals_.reset();
    }
  }

  double signedDistance(const Vec3& p) const override {
    if (!pseudoNormals_) return byParity(p, tree_.distance(p));
    const TriangleTree::Closest closest = closestTo(p);
    if (const auto d = pseudoNormals_->signedDistance(p, closest.face)) return *d;
    return byParity(p, norm(p - closest.point));  // the normal could not tell
  }

private:
  // The closest point to q. The rasteriser asks of neighbouring cells in turn, so the last answer on
  // this thread bounds the search well when q is near the last query (its distance exceeds the true
  // one by at most twice the step), when the step is under the last distance plus a mean edge. After
  // a longer step, a search with no bound (the tree's nearest boxes first).
  TriangleTree::Closest closestTo(const Vec3& q) const {
    struct Last {
      std::uint64_t solid = 0;
      Vec3 query;
      double distance = 0;
      TriangleTree::Closest closest;
    };
    thread_local Last last;
    const bool near = last.solid == id_ && norm(q - last.query) < last.distance + meanEdge_;
    last.closest = near ? tree_.closest(q, last.closest) : tree_.closest(q);
    last.solid = id_, last.query = q, last.distance = norm(q - last.closest.point);
    return last.closest;
  }

  // `distance`, negative where a ray from p crosses the mesh an odd number of times.
  double byParity(const Vec3& p, double distance) const {
    // A direction no mesh of ours is aligned with, so the ray meets edges and vertices almost never.
    return tree_.crossings(p, {0.5773, 0.5802, 0.5743}) % 2 == 1 ? -distance : distance;
  }

  TriangleTree tree_;
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

}  // namespace isoatlas::edit::dvt
