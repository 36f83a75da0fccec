// meshoptSimplify: meshoptimizer's edge-collapse simplifier (meshopt_simplify, any error allowed) to
// a face count, the plain simplification the model's levels are set beside (bench/multires,
// bench/atlas_corpus). Its seconds are the simplifier's alone. It may stop above the count where a
// collapse would change the topology.
#pragma once
#include <meshoptimizer.h>

#include <chrono>

#include "core/mesh.h"

namespace isoatlas::bench {

inline Mesh meshoptSimplify(const Mesh& dense, std::size_t faces, double& seconds) {
  std::vector<float> xyz;
  for (const Vec3& p : dense.positions) xyz.insert(xyz.end(), {float(p.x), float(p.y), float(p.z)});
  std::vector<unsigned> indices(dense.faceVertices.begin(), dense.faceVertices.end()), out(indices.size());
  const auto start = std::chrono::steady_clock::now();
  float error = 0;
  const std::size_t n = meshopt_simplify(out.data(), indices.data(), indices.size(), xyz.data(), dense.vertexCount(),
                                         12, faces * 3, 1.0f, 0, &error);
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  Mesh m;  // the result's faces over all dense vertices, then only the vertices it uses
  m.positions = dense.positions;
  for (std::size_t i = 0; i < n; i += 3) m.addFace({out[i], out[i + 1], out[i + 2]});
  return dropUnusedVertices(m);
}

}  // namespace isoatlas::bench
