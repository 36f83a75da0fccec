// The checks a weld must pass on the dense points it maps again, beyond planWeld's: every point lies
// in a face of the new fan by exact location (locateInFan), and no dense triangle inside the ring
// turns clockwise in the ring's layout (denseTrianglesTurnLeft, over DenseStars).
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh.h"
#include "multires/mapped_points.h"
#include "multires/stellar_operators.h"
#include "multires/vec2.h"
#include "multires/weld_distance.h"
#include "multires/weld_plan.h"

namespace isoatlas::multires::simplify {

// Per dense vertex, the other two corners of each dense face around it, in the face's order: a weld's
// check of the dense triangles reads them in sequence.
struct DenseStars {
  std::vector<std::uint32_t> offsets;
  std::vector<std::array<std::uint32_t, 2>> opposite;

  explicit DenseStars(const Mesh& dense = {});
  std::span<const std::array<std::uint32_t, 2>> of(std::uint32_t v) const {
    return {opposite.data() + offsets[v], offsets[v + 1] - offsets[v]};
  }
};

// Where each point a weld maps again lies in the fan the plan leaves around ring vertex t (u):
// by exact location, or, for a point on the ring's border (no weight on v), in the fan face across
// that border edge with the same weights (its place in the plane, computed in floating point, may
// fall just outside the ring). False when a point lies in no fan face.
// Inputs: v, its oneRing, the ring laid flat (`plane`), the weld's plan (planWeld), and the points
// with where they lie now (ringPoints' `points` and `region`). Output: `hits`, one per point: its fan
// face (m: the face (u, rim[m], rim[m + 1])) and its weights there; meaningful only when it returns
// true (the search stops at the first point in no face).
bool locateInFan(VertexH v, const OneRing& ring, const std::vector<Vec2>& plane, const WeldPlan& plan,
                 const std::vector<FanPoint>& points, const std::vector<MappedPoint>& region,
                 std::vector<TriangleHit>& hits);

// Whether every dense triangle with a corner among the points a weld maps again (v and the dense
// vertices mapped into its ring: inside the ring) and all its corners there or on the ring turns
// counter-clockwise in the ring's layout (exact test).
// Inputs: the dense mesh's stars, its vertex count, the points and where they lie now (ringPoints),
// the ring and its layout. Scratch: `regionIndex` (sized to vertexCount, all -1, on first use; left
// all -1) and `regionPlane`.
bool denseTrianglesTurnLeft(const DenseStars& denseStars, std::size_t vertexCount, const std::vector<FanPoint>& points,
                            const std::vector<MappedPoint>& region, const OneRing& ring, const std::vector<Vec2>& plane,
                            std::vector<std::int32_t>& regionIndex, std::vector<Vec2>& regionPlane);

}  // namespace isoatlas::multires::simplify
