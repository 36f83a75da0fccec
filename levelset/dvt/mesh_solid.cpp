// The one file of levelset/dvt with CGAL's headers.
#include "levelset/dvt/mesh_solid.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <cmath>
#include <vector>

#include "core/error.h"
#include "core/mesh_topology.h"

namespace isoatlas::levelset::dvt {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

class MeshDistance final : public DistanceSolid {
public:
  explicit MeshDistance(const Mesh& mesh) {
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
  }

  double signedDistance(const Vec3& p) const override {
    const Kernel::Point_3 q(p.x, p.y, p.z);
    const double d = std::sqrt(tree_.squared_distance(q));
    // A direction no mesh of ours is aligned with, so the ray meets edges and vertices almost never.
    const Kernel::Ray_3 ray(q, Kernel::Vector_3(0.5773, 0.5802, 0.5743));
    return tree_.number_of_intersected_primitives(ray) % 2 == 1 ? -d : d;
  }

private:
  std::vector<Triangle> triangles_;
  Tree tree_;
};

}  // namespace

std::unique_ptr<DistanceSolid> meshSolid(const Mesh& mesh, const std::string& name) {
  require(mesh.faceCount() > 0 && mesh.allFacesHave(3), name + ": a mesh to voxelise must be triangles");
  const MeshTopology t = analyzeTopology(mesh);
  require(t.closed, name + ": the mesh is not closed (a solid needs a closed surface)");
  return std::make_unique<MeshDistance>(mesh);
}

}  // namespace isoatlas::levelset::dvt
