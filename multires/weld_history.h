// HistoryRecorder: records each weld the simplifier applies as a step of the parametrisation's
// history (ParametrisationHistory): the ring laid flat, the faces the weld replaces (by their
// current versions) and the faces of the fan it leaves, which get new versions. It keeps, per face
// of the simplified mesh, its current version and that version's corners, which the base mesh's
// history frames are made from (compact_base.h).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/mesh.h"
#include "multires/parametrisation_history.h"
#include "multires/stellar_operators.h"
#include "multires/vec2.h"

namespace isoatlas::multires::simplify {

// A face of an applied weld's fan: its handle, its corners (vertex indices) in the face's order, and
// those as local indices of the weld's layout (layoutIndex).
struct FanFace {
  FaceH face;
  std::array<int, 3> corners;
  std::array<std::uint8_t, 3> local;
};

// A vertex's local index in a weld's layout: ring vertex i is i, the removed vertex v is k.
// Throws Error(Failure) for a vertex that is neither.
std::uint8_t layoutIndex(const OneRing& ring, VertexH v, int vertex);

class HistoryRecorder {
public:
  // Inputs: the dense mesh (its face f is version f, with its corners), the simplified mesh's face
  // count (the tables' size) and about how many steps will be recorded (room reserved).
  void start(const Mesh& dense, std::size_t meshFaces, std::size_t steps);

  // The step of an applied weld into the history: the faces it replaced (their versions still those
  // before it), then a new version for each face of its fan.
  // Inputs: the removed vertex v's ring as it was before the weld, its layout (exponentialMap) and
  // the fan's faces (in the ring's order).
  void recordWeld(const OneRing& ring, const std::vector<Vec2>& plane, VertexH v, std::span<const FanFace> fan);

  const std::shared_ptr<ParametrisationHistory>& history() const { return history_; }
  const std::vector<std::uint32_t>& faceVersion() const { return faceVersion_; }
  const std::vector<std::array<int, 3>>& faceCorners() const { return faceCorners_; }

private:
  void recordStep(const OneRing& ring, const std::vector<Vec2>& plane, VertexH v);

  std::shared_ptr<ParametrisationHistory> history_;
  std::vector<std::uint32_t> faceVersion_;       // per face, its version in history_
  std::vector<std::array<int, 3>> faceCorners_;  // per face, its version's corners in order
};

}  // namespace isoatlas::multires::simplify
