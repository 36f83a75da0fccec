#include "core/mesh.h"

#include <algorithm>
#include <unordered_map>

#include "core/polygon_triangulation.h"

namespace isoatlas {

bool Mesh::allFacesHave(std::size_t corners) const {
  for (std::size_t f = 0; f < faceCount(); ++f)
    if (faceOffsets[f + 1] - faceOffsets[f] != corners) return false;
  return true;
}

VertexAdjacency vertexAdjacency(const Mesh& mesh) {
  const std::size_t n = mesh.vertexCount();
  VertexAdjacency a;
  a.faces = vertexFaces(n, mesh.faceCount(), [&](std::size_t f) { return mesh.face(f); });
  const Rows& faces = a.faces;

  // Each edge at v is seen once per face using it; an edge seen once is a boundary edge.
  Rows& neighbours = a.neighbours;
  neighbours.offsets.assign(n + 1, 0);
  a.boundary.assign(n, 0);
  std::vector<std::pair<std::uint32_t, int>> count;  // neighbour, faces using the edge
  for (std::size_t v = 0; v < n; ++v) {
    count.clear();
    for (const std::uint32_t f : faces.of(v)) {
      const auto c = mesh.face(f);
      for (std::size_t i = 0; i < c.size(); ++i) {
        if (c[i] != v) continue;
        for (const std::uint32_t w : {c[(i + 1) % c.size()], c[(i + c.size() - 1) % c.size()]}) {
          auto it = std::find_if(count.begin(), count.end(), [&](const auto& e) { return e.first == w; });
          if (it == count.end()) count.push_back({w, 1});
          else ++it->second;
        }
      }
    }
    for (const auto& [w, uses] : count) {
      neighbours.items.push_back(w);
      if (uses == 1) a.boundary[v] = 1;
    }
    neighbours.offsets[v + 1] = std::uint32_t(neighbours.items.size());
  }
  return a;
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

std::vector<std::array<std::uint32_t, 3>> triangleNeighbours(std::span<const std::array<std::uint32_t, 3>> triangles) {
  std::unordered_map<std::uint64_t, std::uint32_t> halfedge;  // (from, to) -> triangle
  halfedge.reserve(triangles.size() * 3);
  auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
  for (std::uint32_t t = 0; t < triangles.size(); ++t)
    for (int i = 0; i < 3; ++i) halfedge[key(triangles[t][i], triangles[t][(i + 1) % 3])] = t;
  std::vector<std::array<std::uint32_t, 3>> across(triangles.size());
  for (std::uint32_t t = 0; t < triangles.size(); ++t)
    for (int i = 0; i < 3; ++i) {
      const auto it = halfedge.find(key(triangles[t][(i + 1) % 3], triangles[t][i]));
      across[t][i] = it == halfedge.end() ? kNoTriangle : it->second;
    }
  return across;
}

std::vector<Vec3> vertexNormals(const Mesh& m) {
  std::vector<Vec3> n(m.vertexCount(), Vec3{0, 0, 0});
  for (std::size_t f = 0; f < m.faceCount(); ++f) {
    const Vec3 twiceArea = newellNormal(m.positions, m.face(f));
    for (const std::uint32_t v : m.face(f)) n[v] = n[v] + twiceArea;
  }
  for (Vec3& v : n) {
    const double len = norm(v);
    if (len > 0) v = v * (1 / len);
  }
  return n;
}

Mesh triangulated(const Mesh& mesh) {
  Mesh out;
  out.positions = mesh.positions;
  out.normals = mesh.normals;
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto face = mesh.face(f);
    if (face.size() == 3) out.addFace(face);
    else
      for (const auto& t : triangulatePolygon(mesh.positions, face)) out.addFace({t[0], t[1], t[2]});
  }
  return out;
}

double surfaceArea(const Mesh& m) {
  double twice = 0;
  for (std::size_t f = 0; f < m.faceCount(); ++f) twice += norm(newellNormal(m.positions, m.face(f)));
  return twice / 2;
}

Mesh weldIdenticalPositions(const Mesh& mesh) {
  struct Hash {
    std::size_t operator()(const Vec3& p) const {
      return std::hash<double>()(p.x) ^ (std::hash<double>()(p.y) * 31) ^ (std::hash<double>()(p.z) * 131);
    }
  };
  std::unordered_map<Vec3, std::uint32_t, Hash> index;
  Mesh out;
  std::vector<std::uint32_t> to(mesh.vertexCount());
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const auto [it, added] = index.try_emplace(mesh.positions[v], std::uint32_t(out.positions.size()));
    if (added) out.positions.push_back(mesh.positions[v]);
    to[v] = it->second;
  }
  out.faceVertices.reserve(mesh.faceVertices.size());
  for (const std::uint32_t v : mesh.faceVertices) out.faceVertices.push_back(to[v]);
  out.faceOffsets = mesh.faceOffsets;
  return out;
}

}  // namespace isoatlas
