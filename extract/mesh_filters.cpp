#include "extract/mesh_filters.h"

#include <algorithm>

#include "core/union_find.h"

namespace isoatlas::extract {

std::int64_t keepComponents(Mesh& mesh, bool largestOnly, std::int64_t minTriangles) {
  if (!largestOnly && minTriangles <= 0) return 0;
  UnionFind sets(mesh.vertexCount());
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto face = mesh.face(f);
    for (std::size_t i = 1; i < face.size(); ++i) sets.unite(face[i], face[0]);
  }
  std::vector<std::int64_t> size(mesh.vertexCount(), 0);  // triangles per component, at its root
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) ++size[sets.find(mesh.face(f)[0])];
  const std::int64_t largest = size.empty() ? 0 : *std::max_element(size.begin(), size.end());
  // Which components stay, decided once per root; ties for the largest: the first root only.
  std::vector<char> keepRoot(mesh.vertexCount(), 0);
  std::int64_t components = 0, kept = 0;
  bool largestTaken = false;
  for (std::uint32_t v = 0; v < size.size(); ++v) {
    if (sets.parent[v] != v || size[v] == 0) continue;
    ++components;
    const bool keep = largestOnly ? !largestTaken && size[v] == largest : size[v] >= minTriangles;
    largestTaken |= keep && largestOnly;
    keepRoot[v] = keep;
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
