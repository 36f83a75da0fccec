#include "multires/weld_history.h"

#include <algorithm>

#include "core/error.h"

namespace isoatlas::multires::simplify {

std::uint8_t layoutIndex(const OneRing& ring, VertexH v, int vertex) {
  const std::size_t k = ring.vertices.size();
  if (vertex == v.idx()) return std::uint8_t(k);
  for (std::size_t i = 0; i < k; ++i)
    if (ring.vertices[i].idx() == vertex) return std::uint8_t(i);
  throw Error("stellar simplify: a face of the 1-ring has a corner outside it", ErrorKind::Failure);
}

void HistoryRecorder::start(const Mesh& dense, std::size_t meshFaces, std::size_t steps) {
  history_ = std::make_shared<ParametrisationHistory>(std::uint32_t(dense.faceCount()));
  history_->reserve(steps);
  faceVersion_.resize(meshFaces);
  faceCorners_.resize(meshFaces);
  for (std::uint32_t f = 0; f < dense.faceCount(); ++f) {
    faceVersion_[f] = f;
    const auto c = dense.face(f);
    faceCorners_[f] = {int(c[0]), int(c[1]), int(c[2])};
  }
}

// The step of removing v into the history: its ring's layout (v at local index k) and the faces it
// replaces, with their versions' corners as local indices.
void HistoryRecorder::recordStep(const OneRing& ring, const std::vector<Vec2>& plane, VertexH v) {
  const std::size_t k = ring.vertices.size();
  Vec2 layout[kMaxDegree + 1];
  std::copy(plane.begin(), plane.end(), layout);
  layout[k] = {0, 0};
  history_->beginStep({layout, k + 1});
  for (const FaceH f : ring.faces) {
    const auto& c = faceCorners_[f.idx()];
    history_->replaces(faceVersion_[f.idx()], {layoutIndex(ring, v, c[0]), layoutIndex(ring, v, c[1]), layoutIndex(ring, v, c[2])});
  }
}

void HistoryRecorder::recordWeld(const OneRing& ring, const std::vector<Vec2>& plane, VertexH v,
                                 std::span<const FanFace> fan) {
  recordStep(ring, plane, v);
  for (const FanFace& face : fan) {
    faceVersion_[face.face.idx()] = history_->adds(face.local);
    faceCorners_[face.face.idx()] = face.corners;
  }
}

}  // namespace isoatlas::multires::simplify
