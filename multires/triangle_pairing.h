// pairTriangles: covers the base mesh with tiles, pairs of triangles sharing an edge, by a
// maximum-weight matching on the dual graph (LEMON). The weight of a pair ranks the quad's
// orthogonality (1 - mean |cos| of its corner angles), and pairs that would leave a vertex in fewer
// than 3 tiles (2 on the boundary) weigh far less: the paper's "manifoldness". Such a vertex is a
// tile corner of about 180 degrees, where a tile's two triangles, or a renderer's choice of the
// quad's other diagonal, fold over the neighbouring tile.
// Closed meshes always have a perfect matching (Petersen: the dual is cubic and bridgeless); where
// a triangle is left over (odd counts, boundaries), the matching is shifted along an alternating path
// to a triangle with a boundary edge, whose edge is split; the new vertex is sampled from the dense
// surface at the edge's middle. The result is a triquad mesh: every triangle in exactly one tile.
#pragma once
#include "multires/base_mesh.h"

namespace isoatlas::multires {

struct PairingStats {
  std::size_t tiles = 0, splits = 0;
  std::size_t shortVertices = 0;  // vertices in fewer than 3 tiles (2 on the boundary): 0 is the goal
  double meanOrthogonality = 0;  // over the tiles, 1 = all corners right angles
  double seconds = 0;
};

// Inputs: the base mesh and the dense mesh it parametrises. Output: base.tiles filled; base
// triangles, vertices and the parametrisation changed by the splits. Throws Error(Failure) if a
// leftover triangle reaches no boundary (impossible on a manifold).
PairingStats pairTriangles(BaseMesh& base, const Mesh& dense);

// The tiled base mesh's vertices in fewer than 3 tiles (2 on the boundary): PairingStats's
// shortVertices, from base.tiles.
std::size_t shortVertices(const BaseMesh& base);

}  // namespace isoatlas::multires
