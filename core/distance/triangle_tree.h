// TriangleTree: closest points on a triangle mesh and the triangles a ray crosses, by CGAL's AABB tree
// over the mesh's triangles (held by value: building the tree compares and boxes every triangle at
// every depth, and one read through an index misses the cache each time). The one closest-point
// query of isoatlas: mesh_distance.h measures with it, the volume tree's mesh solids voxelise with it.
// A face that names a vertex twice covers nothing and is left out; every answer names a face of the
// mesh by its index.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "core/mesh.h"

namespace isoatlas {

// Whether a triangle names three different vertices; one that names a vertex twice covers nothing
// (the tree leaves it out, and the Hausdorff samples never land on it).
inline bool namesThreeVertices(std::span<const std::uint32_t> triangle) {
  return triangle[0] != triangle[1] && triangle[1] != triangle[2] && triangle[0] != triangle[2];
}

class TriangleTree {
public:
  // How queries without a hint start: from a search tree of the mesh's vertices (built with the
  // tree), or, when every query brings its own hint, from nothing (the search tree is not built).
  enum class Hints { Searched, Given };
  // Throws Error unless the mesh is triangles, at least one of which names three vertices.
  explicit TriangleTree(const Mesh& mesh, Hints hints = Hints::Searched);
  ~TriangleTree();
  TriangleTree(TriangleTree&&) noexcept;

  struct Closest {
    Vec3 point;
    std::uint32_t face = 0;
  };
  // The closest point of the mesh to q. Exact whatever the hint; a hint near the answer (the last
  // answer of a query nearby) only makes the search shorter. Only a tie between two points at the
  // same distance can be decided differently by another hint.
  Closest closest(const Vec3& q) const;  // Hints::Searched only
  Closest closest(const Vec3& q, const Closest& hint) const;
  Vec3 closestPoint(const Vec3& q, const Vec3& hint) const;
  double distance(const Vec3& q) const;  // Hints::Searched only
  // How many triangles the ray from `origin` along `direction` crosses.
  std::size_t crossings(const Vec3& origin, const Vec3& direction) const;

private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace isoatlas
