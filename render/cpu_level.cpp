#include "render/cpu_level.h"

#include <vector>

namespace isoatlas::render {

using multires::EdgeH;

std::size_t refineUniformly(multires::AdaptiveMesh& mesh, int level) {
  std::size_t splits = 0;
  for (int l = 0; l < level; ++l) {
    // One 4-8 level: every edge splittable now (the interior edge of each face at the coarsest level).
    std::vector<EdgeH> edges;
    for (const EdgeH e : mesh.mesh().edges())
      if (mesh.canSplit(e)) edges.push_back(e);
    if (edges.empty()) break;
    for (const EdgeH e : edges)
      if (mesh.canSplit(e)) mesh.split(e), ++splits;
  }
  return splits;
}

std::size_t refineToError(multires::AdaptiveMesh& mesh, const EdgeError& error, double limit) {
  std::size_t splits = 0;
  for (bool changed = true; changed;) {
    changed = false;
    // Edges made by this pass's splits are measured in the next one.
    const std::size_t edges = mesh.mesh().n_edges();
    for (std::size_t i = 0; i < edges; ++i) {
      const EdgeH e{int(i)};
      if (mesh.mesh().status(e).deleted()) continue;
      const auto sample = mesh.splitPosition(e);
      if (!sample) continue;
      const auto& m = mesh.mesh();
      const Vec3 a = multires::toVec3(m.point(m.from_vertex_handle(m.halfedge_handle(e, 0))));
      const Vec3 b = multires::toVec3(m.point(m.to_vertex_handle(m.halfedge_handle(e, 0))));
      if (error(*sample, (a + b) * 0.5) <= limit) continue;
      const std::size_t before = m.n_vertices();
      if (mesh.refine(e)) {
        splits += m.n_vertices() - before;
        changed = true;
      }
    }
  }
  return splits;
}

std::size_t coarsenToError(multires::AdaptiveMesh& mesh, const EdgeError& error, double limit) {
  std::size_t welds = 0;
  for (bool changed = true; changed;) {
    changed = false;
    const auto& m = mesh.mesh();
    for (std::size_t i = 0; i < m.n_vertices(); ++i) {
      const multires::VertexH v{int(i)};
      if (!mesh.canWeld(v)) continue;  // also false for a deleted vertex
      const auto parents = mesh.weldParents(v);
      const Vec3 chord = (multires::toVec3(m.point(parents[0])) + multires::toVec3(m.point(parents[1]))) * 0.5;
      if (error(multires::toVec3(m.point(v)), chord) > limit) continue;
      mesh.weld(v);
      ++welds;
      changed = true;
    }
  }
  if (welds) mesh.compact();
  return welds;
}

}  // namespace isoatlas::render
