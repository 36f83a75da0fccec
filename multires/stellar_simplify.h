// simplifyStellar: simplifies a dense 2-manifold triangle mesh with stellar operators only (edge flips,
// then a face, edge or boundary weld), removing the vertex whose weld costs least by the quadric error
// (Garland and Heckbert; boundary edges add perpendicular planes so borders keep their shape) and,
// near the target size, by the weld's measured largest distance (weldDistance2), and
// keeps a local parametrisation as it goes (Maximo, Velho and Siqueira, section 4.1): the 1-ring of a
// removed vertex is laid flat by an exponential map, and the removed vertex and every dense vertex
// already mapped into that 1-ring are located in the new faces with barycentric coordinates.
// Bijective by construction: a weld is applied only when planWeld finds every step of it valid in
// the ring's layout by exact predicates, every dense point of the ring lies in a face of the new fan
// by exact location, and no dense triangle inside the ring turns clockwise there; each step goes
// into the parametrisation's history (base.history), which maps base points back exactly.
// Every base vertex is an original vertex; the genus and the boundary loops are kept.
// The welds are taken in batches of the cheapest whose regions (v, its target and their rings) do
// not touch: checked, applied to the mesh and ranked again side by side, recorded in the history in
// the batch's order. A batch depends on the ranking alone, so the base mesh does not depend on the
// thread count.
#pragma once
#include <limits>
#include <optional>

#include "multires/base_mesh.h"
#include "multires/stellar_operators.h"

namespace isoatlas::multires {

// The base size when none is asked for: 2 % of the dense vertices up to 1,000 of them, and never
// fewer than 1 % (the paper's ratio). At 1 % a small mesh keeps too few tiles to follow its shape,
// and 2 % still keeps the model smaller than the dense mesh; a large one at 1 % already has
// thousands of tiles, where 2 % costs much time for a gain in RMS but not in the largest distance
// (bench/RESULTS.md, "the default base size").
// A mesh of at most kWholeMeshMostVertices is its own base mesh (a cage already, as a subdivision
// surface's control mesh is): at 2 % it would be a tetrahedron, and two charts cannot follow a cube's
// or a CAD part's creases (level 10 of such cases 23 to 37 dB; whole, 61 dB or more: bench/RESULTS.md,
// "Small meshes whole"). simplifiedBaseVertices is the ratio rule alone.
inline constexpr double kSmallMeshBaseRatio = 0.02, kLargeMeshBaseRatio = 0.01;
inline constexpr std::size_t kSmallMeshMostBaseVertices = 1000, kWholeMeshMostVertices = 100;
std::size_t defaultBaseVertices(std::size_t denseVertices);
std::size_t simplifiedBaseVertices(std::size_t denseVertices);

struct SimplifyOptions {
  std::optional<double> vertexRatio;  // stop at this fraction of the dense vertices, in (0, 1]; unset: defaultBaseVertices
  std::size_t targetVertices = 0;     // when > 0, stop at this many vertices instead
  double maxError = std::numeric_limits<double>::infinity();  // never weld above this RMS distance (mm)
};

// The base size `options` ask of a mesh of denseVertices: targetVertices, else vertexRatio of them
// (at least 4), else defaultBaseVertices.
std::size_t targetBaseVertices(const SimplifyOptions& options, std::size_t denseVertices);

// Welds refused when applied, each until the vertex's ring changes: a dense point of the ring that no
// face of the new fan holds by exact location (it lies within rounding of the ring's border), or a
// dense triangle inside the ring that turns clockwise in its layout.
struct RefusalCounts {
  std::size_t pointOutside = 0, denseTriangle = 0;
};

struct SimplifyStats {
  std::size_t denseVertices = 0, baseVertices = 0, baseTriangles = 0, targetVertices = 0;
  WeldCounts operators;
  RefusalCounts refusals;
  std::size_t historySteps = 0, historyBytes = 0;  // the exact parametrisation's record (base.history)
  double seconds = 0;
  bool reachedTarget = false;  // false when no weld was left that keeps the mesh valid and under maxError
};

// Inputs: `dense`, an oriented 2-manifold triangle mesh (closed or with boundaries); `options`.
// Output: the base mesh with the dense vertices' parametrisation (tiles empty). Throws Error(BadInput)
// for a mesh that is not an oriented 2-manifold of triangles, naming the first problem.
BaseMesh simplifyStellar(const Mesh& dense, const SimplifyOptions& options = {}, SimplifyStats* stats = nullptr);

}  // namespace isoatlas::multires
