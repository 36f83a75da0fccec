// Small filters on triangle meshes that keep them closed and manifold.
//   keepComponents: drops the connected components (by shared vertices) that are not among the
//     `largest` largest (0: no such limit) or have fewer than minTriangles; removes vertices left
//     unused. Ties: the component found first. Returns how many components were removed.
//   taubinSmooth: `iterations` rounds of Laplacian smoothing with lambda, then un-shrinking with mu
//     (Taubin 1995), uniform weights over the 1-ring; only positions move.
#pragma once
#include <cstdint>

#include "core/mesh.h"

namespace isoatlas::extract {

std::int64_t keepComponents(Mesh& mesh, std::size_t largest, std::int64_t minTriangles);
void taubinSmooth(Mesh& mesh, int iterations, double lambda = 0.5, double mu = -0.53);

}  // namespace isoatlas::extract
