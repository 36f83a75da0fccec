#include "extract/mesh_filters.h"

#include <algorithm>
#include <numeric>

namespace isoatlas::extract {

std::int64_t keepComponents(Mesh& mesh, bool largestOnly, std::int64_t minTriangles) {
  if (!largestOnly && minTriangles <= 0) return 0;
  std::vector<std::uint32_t> parent(mesh.vertexCount());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto face = mesh.face(f);
    for (std::size_t i = 1; i < face.size(); ++i) parent[find(face[i])] = find(face[0]);
  }
  std::vector<std::int64_t> size(mesh.vertexCount(), 0);
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) ++size[find(mesh.face(f)[0])];
  const std::int64_t largest = size.empty() ? 0 : *std::max_element(size.begin(), size.end());
  std::int64_t components = 0, kept = 0;
  for (std::uint32_t v = 0; v < parent.size(); ++v)
    if (parent[v] == v && size[v] > 0) ++components;
  auto keep = [&](std::uint32_t root) {
    return largestOnly ? size[root] == largest : size[root] >= minTriangles;
  };
  bool largestTaken = false;
  std::uint32_t largestRoot = UINT32_MAX;
  std::vector<char> rootKept(mesh.vertexCount(), 0);
  Mesh out = selectFaces(mesh, [&](std::size_t f) {
    const std::uint32_t root = find(mesh.face(f)[0]);
    if (!keep(root)) return false;
    if (largestOnly) {  // ties: the first largest component only
      if (!largestTaken) largestTaken = true, largestRoot = root;
      if (root != largestRoot) return false;
    }
    rootKept[root] = 1;
    return true;
  });
  for (std::uint32_t v = 0; v < parent.size(); ++v) kept += rootKept[v];
  mesh = std::move(out);
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
