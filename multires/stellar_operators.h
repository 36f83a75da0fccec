// The stellar operators on a StellarMesh (Velho's stellar theory, as the paper uses it): edge flip,
// face weld (remove a vertex of degree 3), edge weld (remove a vertex of degree 4, leaving an edge),
// boundary weld (remove a boundary vertex of two faces, leaving its boundary edge) and edge split.
// Each changes only the 1-ring of the vertex it removes or adds.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "multires/stellar_mesh.h"

namespace isoatlas::multires {

// The most neighbours a vertex may have for a weld (its 1-ring then fits fixed arrays); a vertex of
// higher degree is left in place.
inline constexpr std::size_t kMaxDegree = 64;

// The 1-ring of v in the orientation of its faces: neighbours w_0 .. w_{k-1}, faces[i] = (v, w_i, w_i+1)
// (indices mod k). For a boundary vertex w_0 and w_{k-1} are its boundary neighbours and faces has
// k - 1 entries.
struct OneRing {
  std::vector<VertexH> vertices;
  std::vector<FaceH> faces;
  bool boundary = false;
};
OneRing oneRing(const StellarMesh& mesh, VertexH v);
void oneRing(const StellarMesh& mesh, VertexH v, OneRing& ring);  // reuses ring's storage

// Per vertex, its number of neighbours. On a big mesh, walking round a vertex to count them is a
// chain of cache misses; a simplifier that asks canWeldInto millions of times keeps this table
// instead (weldInto updates it) and passes it along.
using DegreeTable = std::vector<std::uint32_t>;
DegreeTable degreeTable(const StellarMesh& mesh);

// Whether weldInto(v, u) keeps the mesh a 2-manifold of the same topology: u a neighbour of v
// (along the boundary when v is a boundary vertex), the link condition holds, no boundary loop drops
// below three edges and no vertex drops below three neighbours. `degrees`, when given, must be
// current.
bool canWeldInto(const StellarMesh& mesh, VertexH v, VertexH u, const DegreeTable* degrees = nullptr);

struct WeldCounts {
  int flips = 0, faceWelds = 0, edgeWelds = 0, boundaryWelds = 0;
  WeldCounts& operator+=(const WeldCounts& o) {
    flips += o.flips, faceWelds += o.faceWelds, edgeWelds += o.edgeWelds, boundaryWelds += o.boundaryWelds;
    return *this;
  }
};

// Removes v, leaving its 1-ring triangulated as a fan around its neighbour u: edge flips bring v to
// degree 4 (an interior vertex) or to two faces (a boundary vertex), then an edge weld, or a face weld
// when v already had degree 3, or a boundary weld. Requires canWeldInto(mesh, v, u). The faces of
// the 1-ring that remain keep their handles; v and two faces (one at the boundary) are deleted.
// `degrees`, when given, is kept current (only u and its neighbours change). `spokes`, when given, are
// the far ends of the edges to flip, in order (planWeld's, each a neighbour of v next to u when its
// turn comes); else the spokes next to u on one side are flipped.
WeldCounts weldInto(StellarMesh& mesh, VertexH v, VertexH u, DegreeTable* degrees = nullptr,
                    std::span<const VertexH> spokes = {});

// Splits edge e at a new vertex placed at `position`, joined to the opposite vertices (the inverse
// of an edge weld or, on the boundary, of a boundary weld). Returns the new vertex.
VertexH splitEdge(StellarMesh& mesh, EdgeH e, const Vec3& position);

}  // namespace isoatlas::multires
