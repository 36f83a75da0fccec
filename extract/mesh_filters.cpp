#include "extract/mesh_filters.h"

#include <algorithm>

#include "core/union_find.h"

namespace isoatlas::extract {

std::int64_t keepComponents(Mesh& mesh, std::size_t largest, std::int64_t minTriangles) {
  if (largest == 0 && minTriangles <= 0) return 0;
  UnionFind sets(mesh.vertexCount());
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto face = mesh.face(f);
    for (std::size_t i = 1; i < face.size(); ++i) sets.unite(face[i], face[0]);
  }
  std::vector<std::int64_t> size(mesh.vertexCount(), 0);  // triangles per component, at its root
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) ++size[sets.find(mesh.face(f)[0])];
  // The components' roots, largest first (a stable sort: ties in the order found).
  std::vector<std::uint32_t> roots;
  for (std::uint32_t v = 0; v < size.size(); ++v)
    if (sets.parent[v] == v && size[v] > 0) roots.push_back(v);
  std::stable_sort(roots.begin(), roots.end(), [&](std::uint32_t a, std::uint32_t b) { return size[a] > size[b]; });
  std::vector<char> keepRoot(mesh.vertexCount(), 0);
  const std::int64_t components = std::int64_t(roots.size());
  std::int64_t kept = 0;
  for (std::size_t k = 0; k < roots.size(); ++k) {
    const bool keep = (largest == 0 || k < largest) && size[roots[k]] >= minTriangles;
    keepRoot[roots[k]] = keep;
    kept += keep;
  }
  mesh = selectFaces(mesh, [&](std::size_t f) { return keepRoot[sets.find(mesh.face(f)[0])] != 0; });
  return components - kept;
}

void taubinSmooth(Mesh& mesh, int iterations, double lambda, double mu) {
  if (iterations <= 0) return;
  const Rows ring = vertexAdjacency(mesh).neighbours;
  std::vector<Vec3> next(mesh.vertexCount());
  auto pass = [&](double factor) {
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
      const auto around = ring.of(v);
      if (around.empty()) {
        next[v] = mesh.positions[v];
        continue;
      }
      Vec3 mean{0, 0, 0};
      for (const std::uint32_t n : around) mean = mean + mesh.positions[n];
      mean = mean * (1.0 / double(around.size()));
      next[v] = mesh.positions[v] + (mean - mesh.positions[v]) * factor;
    }
    mesh.positions.swap(next);
  };
  for (int i = 0; i < iterations; ++i) {
    pass(lambda);
    pass(mu);
  }
  mesh.normals.clear();  // no longer match the moved positions
}

}  // namespace isoatlas::extract
