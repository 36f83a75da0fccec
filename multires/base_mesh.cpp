#include "multires/base_mesh.h"

#include "core/error.h"

namespace isoatlas::multires {

Mesh BaseMesh::triangleMesh() const {
  Mesh mesh;
  mesh.positions = positions;
  for (const auto& t : triangles) mesh.addFace({t[0], t[1], t[2]});
  return mesh;
}

std::pair<std::uint32_t, std::array<double, 3>> BaseMesh::chartToTriangle(std::uint32_t tile, double u, double v) const {
  const auto [first, second] = tiles.at(tile);
  const auto& a = triangles[first];
  const auto& b = triangles[second];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (b[j] == a[(i + 1) % 3] && b[(j + 1) % 3] == a[i]) {
        std::array<double, 3> w{};
        if (v >= u) {  // first = (p, q, r): (u, v) = u (q - p) + (v - u) (r - p) from p
          w[i] = 1 - v, w[(i + 1) % 3] = u, w[(i + 2) % 3] = v - u;
          return {first, w};
        }
        // second = (q, p, s) starting at corner j: (u, v) = (1,1) + (1 - u) (p - q) + (u - v) (s - q)
        w[j] = v, w[(j + 1) % 3] = 1 - u, w[(j + 2) % 3] = u - v;
        return {second, w};
      }
  throw Error("base mesh: a tile's two triangles share no edge", ErrorKind::Failure);
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
