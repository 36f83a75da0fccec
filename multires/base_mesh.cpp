#include "multires/base_mesh.h"

#include <unordered_map>

#include "core/error.h"

namespace isoatlas::multires {

std::vector<std::array<std::uint32_t, 3>> BaseMesh::triangleNeighbours() const { return isoatlas::triangleNeighbours(triangles); }

Mesh BaseMesh::triangleMesh() const {
  Mesh mesh;
  mesh.positions = positions;
  for (const auto& t : triangles) mesh.addFace({t[0], t[1], t[2]});
  return mesh;
}

BaseMesh::TileCorners BaseMesh::tileCorners(std::uint32_t tile) const {
  const auto& a = triangles[tiles.at(tile)[0]];
  const auto& b = triangles[tiles[tile][1]];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (b[j] == a[(i + 1) % 3] && b[(j + 1) % 3] == a[i]) return {a[i], b[(j + 2) % 3], a[(i + 1) % 3], a[(i + 2) % 3], i, j};
  throw Error("base mesh: tile " + std::to_string(tile) + "'s triangles share no edge", ErrorKind::Failure);
}

std::pair<std::uint32_t, std::array<double, 3>> BaseMesh::chartToTriangle(std::uint32_t tile, double u, double v) const {
  const TileCorners c = tileCorners(tile);
  const int i = c.first, j = c.second;
  std::array<double, 3> w{};
  if (v >= u) {  // first = (p, q, r): (u, v) = u (q - p) + (v - u) (r - p) from p
    w[i] = 1 - v, w[(i + 1) % 3] = u, w[(i + 2) % 3] = v - u;
    return {tiles[tile][0], w};
  }
  // second = (q, p, s) starting at corner j: (u, v) = (1,1) + (1 - u) (p - q) + (u - v) (s - q)
  w[j] = v, w[(j + 1) % 3] = 1 - u, w[(j + 2) % 3] = u - v;
  return {tiles[tile][1], w};
}

std::array<double, 2> BaseMesh::triangleToChart(std::uint32_t tile, std::uint32_t triangle, const std::array<double, 3>& bary) const {
  const TileCorners c = tileCorners(tile);
  if (triangle == tiles[tile][0]) return {bary[std::size_t((c.first + 1) % 3)], 1 - bary[std::size_t(c.first)]};
  require(triangle == tiles[tile][1], "base mesh: triangle " + std::to_string(triangle) + " is not in tile " + std::to_string(tile));
  return {1 - bary[std::size_t((c.second + 1) % 3)], bary[std::size_t(c.second)]};
}

Mesh BaseMesh::quadMesh() const {
  require(tiles.size() * 2 == triangles.size(), "base mesh: the triangles are not all paired into tiles");
  Mesh mesh;
  mesh.positions = positions;
  for (std::uint32_t t = 0; t < tiles.size(); ++t) {
    const TileCorners c = tileCorners(t);
    mesh.addFace({c.p, c.s, c.q, c.r});
  }
  return mesh;
}

}  // namespace isoatlas::multires
