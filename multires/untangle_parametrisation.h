// untangleParametrisation: makes the parametrisation one-to-one where it folds. Every simplification
// step maps the dense vertices by a bijection, but a dense triangle drawn straight between its mapped
// corners can still turn over in the base domain (its edges were bent by earlier steps), and a
// folded image makes one parameter point name two places of the surface. Each free vertex of a
// folded triangle (then, when that stalls, its neighbours too) is moved into the kernel of its link,
// where all its triangles turn counter-clockwise (else to its neighbours' average, Tutte's step),
// in one chart of the base domain that holds its neighbours; a move is kept only when it leaves fewer
// or shallower folds around the vertex, so the count never grows. Base vertices and dense boundary
// vertices stay. Not guaranteed to reach zero: a dense triangle whose corners lie in base triangles
// sharing no vertex has no chart and counts as folded.
#pragma once
#include <cstddef>

#include "multires/base_mesh.h"

namespace isoatlas::multires {

struct UntangleStats {
  std::size_t foldedBefore = 0, foldedAfter = 0;  // dense triangles whose image is clockwise or flat
  std::size_t movedVertices = 0;                  // dense vertices moved at least once
  double seconds = 0;
};

// Inputs: the dense mesh and its base mesh with the parametrisation (denseTriangle, denseBary).
// Output: the parametrisation, changed in place for the relaxed vertices.
UntangleStats untangleParametrisation(const Mesh& dense, BaseMesh& base);

// The dense triangles whose image in the base domain (in the chart BaseDomain::chartFor gives its
// corners) is clockwise or flat, or whose corners lie in base triangles that share no vertex.
std::size_t countFoldedTriangles(const Mesh& dense, const BaseMesh& base);

}  // namespace isoatlas::multires
