// MappedPoint and ringPoints: the removed dense vertices the simplifier keeps mapped into the faces of
// the mesh it simplifies (each where it lies in its face, by weights of the face's corners), and the
// points a weld of a vertex maps again (the vertex and those mapped into its ring), which both the
// weld's ranking (weldDistance2) and its check (weld_fan_checks.h) read.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "core/vec.h"
#include "multires/stellar_operators.h"
#include "multires/vec2.h"
#include "multires/weld_distance.h"

namespace isoatlas::multires::simplify {

// A removed dense vertex where it lies: weights of the vertices of the face that holds it. Each face
// keeps its points together, with their positions, so that a ring's points are read in sequence.
struct MappedPoint {
  std::uint32_t id;  // the dense vertex
  std::array<int, 3> vertices;
  std::array<double, 3> bary;
  Vec3 position;
};

// Per face of the simplified mesh (by handle index), the removed dense vertices mapped into it.
using FacePoints = std::vector<std::vector<MappedPoint>>;

inline Vec3 pointOf(const StellarMesh& mesh, VertexH v) { return toVec3(mesh.point(v)); }

// The points a weld of v maps again: v and every dense vertex mapped into its ring's faces, in space
// and in the ring's flat map `plane`; `region`, when given, gets where they lie now (v: at itself).
// Inputs: the mesh, `facePoints` (the points mapped into each face), v, its oneRing and the ring laid
// flat (exponentialMap: v at the origin). Outputs: `points` (v first) and, when given, `region`, one
// entry per point in the same order.
void ringPoints(const StellarMesh& mesh, const FacePoints& facePoints, VertexH v, const OneRing& ring,
                const std::vector<Vec2>& plane, std::vector<FanPoint>& points, std::vector<MappedPoint>* region);

}  // namespace isoatlas::multires::simplify
