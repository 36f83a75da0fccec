// The one file of levelset/dvt with CGAL's headers.
#include "levelset/dvt/mesh_solid.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <cmath>
#include <optional>
#include <vector>

#include "core/error.h"
#include "core/mesh_topology.h"
#include "levelset/dvt/mesh_sign.h"

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
    tree_.insert(triangles_.begin(), triangles_.end());
    tree_.accelerate_distance_queries();
    if (oriented) {
      pseudoNormals_.emplace(mesh, [&](const Vec3& p) { return byParity(p, 1) < 0; });
      if (!pseudoNormals_->usable()) pseudoNormals_.reset();
    }
  }

  double signedDistance(const Vec3& p) const override {
    if (pseudoNormals_) {
      const auto [closest, triangle] = tree_.closest_point_and_primitive(Kernel::Point_3(p.x, p.y, p.z));
      if (const auto d = pseudoNormals_->signedDistance(p, std::size_t(triangle - triangles_.begin()))) return *d;
    }
    const Kernel::Point_3 q(p.x, p.y, p.z);
    return byParity(p, std::sqrt(tree_.squared_distance(q)));
  }

private:
  // `distance`, negative where a ray from p crosses the mesh an odd number of times.
  double byParity(const Vec3& p, double distance) const {
    // A direction no mesh of ours is aligned with, so the ray meets edges and vertices almost never.
    const Kernel::Ray_3 ray(Kernel::Point_3(p.x, p.y, p.z), Kernel::Vector_3(0.5773, 0.5802, 0.5743));
    return tree_.number_of_intersected_primitives(ray) % 2 == 1 ? -distance : distance;
  }

  std::vector<Triangle> triangles_;
  Tree tree_;
  std::optional<PseudoNormals> pseudoNormals_;  // the side without a ray, where the mesh is oriented
};

}  // namespace

std::unique_ptr<DistanceSolid> meshSolid(const Mesh& mesh, const std::string& name) {
  require(mesh.faceCount() > 0 && mesh.allFacesHave(3), name + ": a mesh to voxelise must be triangles");
  const MeshTopology t = analyzeTopology(mesh);
  require(t.closed, name + ": the mesh is not closed (a solid needs a closed surface)");
  return std::make_unique<MeshDistance>(mesh, t.oriented);
}

}  // namespace isoatlas::levelset::dvt
