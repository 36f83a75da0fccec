// The CPU stage of the cascade: chooses the adaptive mesh's resolution by stellar splits under the
// one-level rule (multires::AdaptiveMesh::refine), starting from the base tiles.
//   refineUniformly(mesh, level): every face to `level`, or to the chart's texels where that is
//                                 coarser; returns the splits made
//   refineToError(mesh, error, limit): splits every edge whose split point lies farther than `limit`
//                                 from the edge's midpoint, as `error` measures it (pixels on the
//                                 screen for a view, millimetres for a region), until none does or
//                                 the chart's texels are reached; the forced splits come along
//   coarsenToError(mesh, error, limit): welds every weldable vertex that lies within `limit` of the
//                                 midpoint of the edge it was split from, until none does; returns
//                                 the welds (the mesh is compacted when there were some)
// Coarsening then refining moves a mesh from one view's level to the next: only where the view
// changed does anything split or weld.
#pragma once
#include <functional>

#include "multires/adaptive_mesh.h"

namespace isoatlas::render {

std::size_t refineUniformly(multires::AdaptiveMesh& mesh, int level);

// error(sample, chordMidpoint): the error of leaving the sample out, in the caller's unit.
using EdgeError = std::function<double(const Vec3& sample, const Vec3& chordMidpoint)>;
std::size_t refineToError(multires::AdaptiveMesh& mesh, const EdgeError& error, double limit);
std::size_t coarsenToError(multires::AdaptiveMesh& mesh, const EdgeError& error, double limit);

}  // namespace isoatlas::render
