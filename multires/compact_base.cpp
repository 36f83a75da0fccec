#include "multires/compact_base.h"

#include <array>
#include <cstdint>
#include <vector>

namespace isoatlas::multires::simplify {

BaseMesh compactBase(const StellarMesh& mesh, const HistoryRecorder& history, const FacePoints& facePoints) {
  const std::vector<std::uint32_t>& faceVersion = history.faceVersion();
  const std::vector<std::array<int, 3>>& faceCorners = history.faceCorners();
  BaseMesh base;
  std::vector<std::uint32_t> vertexIndex(mesh.n_vertices(), ~0u), faceIndex(mesh.n_faces(), ~0u);
  for (const VertexH v : mesh.vertices()) {
    vertexIndex[v.idx()] = std::uint32_t(base.positions.size());
    base.positions.push_back(pointOf(mesh, v));
    base.denseVertex.push_back(v.idx());
  }
  for (const FaceH f : mesh.faces()) {
    faceIndex[f.idx()] = std::uint32_t(base.triangles.size());
    std::array<std::uint32_t, 3> t{};
    HistoryFrame frame{faceVersion[f.idx()], {}};
    int i = 0;
    for (const VertexH v : mesh.fv_range(f)) {
      t[i] = vertexIndex[v.idx()];
      for (int j = 0; j < 3; ++j) frame.corner[i][j] = faceCorners[f.idx()][j] == v.idx() ? 1 : 0;
      ++i;
    }
    base.triangles.push_back(t);
    base.historyFrames.push_back(frame);
  }
  base.history = history.history();
  const std::size_t n = mesh.n_vertices();
  base.denseTriangle.resize(n);
  base.denseBary.resize(n);
  for (std::size_t d = 0; d < n; ++d) {
    const VertexH v{int(d)};
    if (!mesh.status(v).deleted()) {
      // A base vertex: a corner of any of its faces.
      const HalfedgeH h = mesh.halfedge_handle(v);
      const FaceH f = mesh.is_boundary(h) ? mesh.face_handle(mesh.opposite_halfedge_handle(h)) : mesh.face_handle(h);
      const std::uint32_t t = faceIndex[f.idx()];
      base.denseTriangle[d] = t;
      base.denseBary[d] = {0, 0, 0};
      for (int c = 0; c < 3; ++c)
        if (base.triangles[t][c] == vertexIndex[d]) base.denseBary[d][c] = 1;
      continue;
    }
  }
  for (const FaceH f : mesh.faces()) {
    const std::uint32_t t = faceIndex[f.idx()];
    for (const MappedPoint& m : facePoints[f.idx()]) {
      base.denseTriangle[m.id] = t;
      for (int c = 0; c < 3; ++c)
        for (int j = 0; j < 3; ++j)
          if (base.triangles[t][c] == vertexIndex[m.vertices[j]]) base.denseBary[m.id][c] = m.bary[j];
    }
  }
  return base;
}

}  // namespace isoatlas::multires::simplify
