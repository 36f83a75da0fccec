#include "multires/base_mesh.h"

#include "core/error.h"

namespace isoatlas::multires {

Mesh BaseMesh::triangleMesh() const {
  Mesh mesh;
  mesh.positions = positions;
  for (const auto& t : triangles) mesh.addFace({t[0], t[1], t[2]});
  return mesh;
}

Mesh BaseMesh::quadMesh() const {
  require(tiles.size() * 2 == triangles.size(), "base mesh: the triangles are not all paired into tiles");
  Mesh mesh;
  mesh.positions = positions;
  for (const auto& tile : tiles) {
    const auto& a = triangles[tile[0]];
    const auto& b = triangles[tile[1]];
    // a = (p, q, r) with the shared edge (p, q); b runs it the other way and adds its apex s.
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t p = a[i], q = a[(i + 1) % 3], r = a[(i + 2) % 3];
      for (int j = 0; j < 3; ++j)
        if (b[j] == q && b[(j + 1) % 3] == p) {
          mesh.addFace({p, b[(j + 2) % 3], q, r});
          goto next;
        }
    }
    throw Error("base mesh: a tile's two triangles share no edge", ErrorKind::Failure);
  next:;
  }
  return mesh;
}

}  // namespace isoatlas::multires
