// countFoldedTriangles: how many dense triangles, drawn straight between their vertices' places on
// the base mesh (BaseMesh::denseTriangle, denseBary) in the one chart of the base domain that holds
// their corners (BaseDomain::chartFor), turn clockwise or flat there. A measure of the forward
// parametrisation's distortion: the atlas does not draw dense triangles (it samples the dense surface
// through the exact history, ParametrisationHistory), so a dense triangle counted here folds no
// texel. Where one base triangle holds all three corners (a corner on a base vertex lies in every
// triangle around it: a mesh kept whole, its own base), its own frame draws the triangle; corners in
// base triangles that share no vertex have no chart and count as folded.
#pragma once
#include <cstddef>

#include "multires/base_mesh.h"

namespace isoatlas::multires {

std::size_t countFoldedTriangles(const Mesh& dense, const BaseMesh& base);

}  // namespace isoatlas::multires
