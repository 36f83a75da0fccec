// exponentialMap: lays a vertex's 1-ring flat around it, keeping the distances to the neighbours and
// scaling the angles between them to a full turn (a half turn for a boundary vertex, which then lies
// on the straight line between its boundary neighbours). The local parametrisation of a stellar weld.
#pragma once
#include <cmath>
#include <vector>

#include "multires/stellar_operators.h"
#include "multires/vec2.h"

namespace isoatlas::multires {

// Inputs: the mesh, the vertex v and its oneRing. Output: `plane`, the plane position of each ring
// vertex (v at the origin), in ring order. Returns false when the ring is degenerate (a zero-length
// edge, a zero total angle) or has more than kMaxDegree vertices.
bool exponentialMap(const StellarMesh& mesh, VertexH v, const OneRing& ring, std::vector<Vec2>& plane);

}  // namespace isoatlas::multires
