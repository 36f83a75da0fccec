// TriangleTree: closest points on a triangle mesh and the triangles a ray crosses, by a bounding
// volume hierarchy of our own over the mesh's triangles (held by value, in the Morton order of their
// centroids), whose answers are CGAL's: each closest point is CGAL's projection onto its triangle,
// each crossing CGAL's ray-triangle test. The one closest-point query of isoatlas: mesh_distance.h
// measures with it, the volume tree's mesh solids voxelise with it.
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
  // Throws Error unless the mesh is triangles, at least one of which names three vertices.
  explicit TriangleTree(const Mesh& mesh);
  ~TriangleTree();
  TriangleTree(TriangleTree&&) noexcept;

  struct Closest {
    Vec3 point;
    std::uint32_t face = 0;
  };
  // The closest point of the mesh to q. Exact whatever the hint; a hint near the answer (the last
  // answer of a query nearby) only makes the search shorter. Only a tie between two points at the
  // same distance can be decided differently by another hint.
  Closest closest(const Vec3& q) const;
  Closest closest(const Vec3& q, const Closest& hint) const;
  Vec3 closestPoint(const Vec3& q, const Vec3& hint) const;
  double distance(const Vec3& q) const;
  // How many triangles the ray from `origin` along `direction` crosses.
  std::size_t crossings(const Vec3& origin, const Vec3& direction) const;

private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace isoatlas
