#include "core/distance/triangle_tree.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Simple_cartesian.h>

#include <cmath>
#include <vector>

#include "core/error.h"

namespace isoatlas {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;

struct FaceTriangle {
  Kernel::Triangle_3 triangle;
  std::uint32_t face;
};

// CGAL's AABB_triangle_primitive, but holding its triangle and naming it by its face. The same datum
// and reference point (the first corner), so the same tree and answers as CGAL's own primitive.
class HeldTriangle {
public:
  using Point = Kernel::Point_3;
  using Datum = Kernel::Triangle_3;
  using Id = std::uint32_t;
  using Datum_reference = const Datum&;
  using Point_reference = const Point&;
  HeldTriangle() = default;
  explicit HeldTriangle(std::vector<FaceTriangle>::const_iterator t) : datum_(t->triangle), id_(t->face) {}
  const Datum& datum() const { return datum_; }
  Id id() const { return id_; }
  const Point& reference_point() const { return datum_.vertex(0); }

private:
  Datum datum_;
  Id id_ = 0;
};
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, HeldTriangle>>;

Point point(const Vec3& p) { return {p.x, p.y, p.z}; }
Vec3 vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

}  // namespace

struct TriangleTree::State {
  Tree tree;
};

TriangleTree::TriangleTree(const Mesh& mesh, Hints hints) : state_(std::make_unique<State>()) {
  require(mesh.allFacesHave(3), "a closest-point tree needs a triangle mesh");
  std::vector<FaceTriangle> triangles;
  triangles.reserve(mesh.faceCount());
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto c = mesh.face(f);
    if (!namesThreeVertices(c)) continue;
    const auto at = [&](int k) { return point(mesh.positions[c[k]]); };
    triangles.push_back({Kernel::Triangle_3(at(0), at(1), at(2)), std::uint32_t(f)});
  }
  require(!triangles.empty(), "a closest-point tree needs a triangle that names three vertices");
  if (hints == Hints::Given) state_->tree.do_not_accelerate_distance_queries();
  state_->tree.rebuild(triangles.begin(), triangles.end());
  if (hints == Hints::Searched) state_->tree.accelerate_distance_queries();
}

TriangleTree::~TriangleTree() = default;
TriangleTree::TriangleTree(TriangleTree&&) noexcept = default;

TriangleTree::Closest TriangleTree::closest(const Vec3& q) const {
  const auto [p, face] = state_->tree.closest_point_and_primitive(point(q));
  return {vec(p), face};
}

TriangleTree::Closest TriangleTree::closest(const Vec3& q, const Closest& hint) const {
  const auto [p, face] = state_->tree.closest_point_and_primitive(point(q), {point(hint.point), hint.face});
  return {vec(p), face};
}

Vec3 TriangleTree::closestPoint(const Vec3& q, const Vec3& hint) const { return vec(state_->tree.closest_point(point(q), point(hint))); }

double TriangleTree::distance(const Vec3& q) const { return std::sqrt(state_->tree.squared_distance(point(q))); }

std::size_t TriangleTree::crossings(const Vec3& origin, const Vec3& direction) const {
  return state_->tree.number_of_intersected_primitives(Kernel::Ray_3(point(origin), Kernel::Vector_3(direction.x, direction.y, direction.z)));
}

}  // namespace isoatlas
