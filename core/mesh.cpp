#include "core/mesh.h"

#include <algorithm>

namespace isoatlas {

bool Mesh::allFacesHave(std::size_t corners) const {
  for (std::size_t f = 0; f < faceCount(); ++f)
    if (faceOffsets[f + 1] - faceOffsets[f] != corners) return false;
  return true;
}

Mesh selectFaces(const Mesh& mesh, const std::function<bool(std::size_t)>& keep) {
  Mesh out;
  std::vector<std::uint32_t> remap(mesh.vertexCount(), UINT32_MAX), corners;
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    if (!keep(f)) continue;
    corners.clear();
    for (const std::uint32_t v : mesh.face(f)) {
      if (remap[v] == UINT32_MAX) {
        remap[v] = std::uint32_t(out.positions.size());
        out.positions.push_back(mesh.positions[v]);
        if (!mesh.normals.empty()) out.normals.push_back(mesh.normals[v]);
      }
      corners.push_back(remap[v]);
    }
    out.addFace(corners);
  }
  return out;
}

Box boundingBox(const std::vector<Vec3>& points) {
  if (points.empty()) return {};
  Box b{points[0], points[0]};
  for (const Vec3& p : points)
    for (int a = 0; a < 3; ++a) {
      b.min[a] = std::min(b.min[a], p[a]);
      b.max[a] = std::max(b.max[a], p[a]);
    }
  return b;
}

}  // namespace isoatlas
