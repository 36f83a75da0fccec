// compactBase: the base mesh the simplifier leaves, its live vertices and faces renumbered in order,
// with each face's history frame (its version in the parametrisation's history and how its corners
// map to that version's) and every dense vertex's place on it: a base vertex at a corner of one of
// its faces, a removed one where it was last mapped (its face's points).
#pragma once
#include "multires/base_mesh.h"
#include "multires/mapped_points.h"
#include "multires/stellar_mesh.h"
#include "multires/weld_history.h"

namespace isoatlas::multires::simplify {

// Inputs: the simplified mesh (removed elements still in place, deleted), the history recorded of
// its welds (each face's version and corners) and the dense vertices mapped into each face.
// Output: the base mesh with its history (shared with the recorder) and its dense vertices'
// parametrisation (tiles empty).
BaseMesh compactBase(const StellarMesh& mesh, const HistoryRecorder& history, const FacePoints& facePoints);

}  // namespace isoatlas::multires::simplify
