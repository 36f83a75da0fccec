// forEach: a loop over a batch's items, side by side when asked (tbb::parallel_for), and fetchAhead,
// the prefetch the simplifier's loops over far-apart vertices make as they go.
#pragma once
#include <cstddef>

#include <tbb/parallel_for.h>

#include "multires/stellar_mesh.h"

namespace isoatlas::multires::simplify {

// f(i) for every i < n: side by side when `parallel` (the results must not depend on the order).
template <class F>
void forEach(std::size_t n, bool parallel, const F& f) {
  if (parallel && n > 1)
    tbb::parallel_for(std::size_t(0), n, f);
  else
    for (std::size_t i = 0; i < n; ++i) f(i);
}

// The vertices a batch ranks or checks lie far apart: while vertex i of n is worked on, the records
// a walk round the next ones starts from are fetched, two ahead the vertex's, one ahead its first
// halfedge's (whose handle the vertex's holds). vertexAt(j) gives vertex j of the n.
template <class VertexAt>
void fetchAhead(const StellarMesh& mesh, std::size_t i, std::size_t n, const VertexAt& vertexAt) {
  if (i + 2 < n) __builtin_prefetch(&mesh.vertex(vertexAt(i + 2)));
  if (i + 1 < n)
    if (const HalfedgeH h = mesh.halfedge_handle(vertexAt(i + 1)); h.is_valid()) __builtin_prefetch(&mesh.halfedge(h));
}

}  // namespace isoatlas::multires::simplify
