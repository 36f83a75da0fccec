// Comparing the meshes of two marching-cubes paths (the CPU's and the GPU's, or one path's two ways of
// reading the field).
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/mesh.h"

namespace isoatlas::extract::test_mesh {

// Both paths number vertices by grid edge and triangles by cell, the CPU across the grid and the GPU
// block by block. So a mesh is put in a canonical numbering first: edge vertices in (point, axis)
// order (the axis is the coordinate off the grid: crossings stay 1e-3 from grid points), centre
// vertices after them by cell and position; each triangle rotated to start at its least vertex, the
// list sorted.
struct CanonicalMesh {
  std::vector<Vec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};
inline CanonicalMesh canonical(const Mesh& m) {
  auto key = [](const Vec3& p) {
    std::array<double, 5> k{};  // z, y, x of the lower grid point or cell, axis (3: a centre), then x
    int offGrid = 0, axis = 3;
    for (int a = 0; a < 3; ++a)
      if (std::fabs(p[a] - std::round(p[a])) > 1e-4) ++offGrid, axis = a;
    if (offGrid > 1) axis = 3;
    for (int a = 0; a < 3; ++a) k[std::size_t(2 - a)] = axis == a || axis == 3 ? std::floor(p[a]) : std::round(p[a]);
    k[3] = axis;
    k[4] = axis == 3 ? p.x + 1e3 * p.y : 0;  // centres sharing a cell, apart by position
    return k;
  };
  std::vector<std::uint32_t> order(m.vertexCount());
  std::vector<std::array<double, 5>> keys(m.vertexCount());
  for (std::uint32_t v = 0; v < order.size(); ++v) order[v] = v, keys[v] = key(m.positions[v]);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
  CanonicalMesh c;
  std::vector<std::uint32_t> rank(order.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) rank[order[i]] = i, c.positions.push_back(m.positions[order[i]]);
  for (std::size_t f = 0; f < m.faceCount(); ++f) {
    const auto t = m.face(f);
    std::array<std::uint32_t, 3> r{rank[t[0]], rank[t[1]], rank[t[2]]};
    std::rotate(r.begin(), std::min_element(r.begin(), r.end()), r.end());
    c.triangles.push_back(r);
  }
  std::sort(c.triangles.begin(), c.triangles.end());
  return c;
}

// The same mesh up to numbering: the same vertices (positions to 1e-5) and the same oriented triangles.
inline void expectSameMesh(const Mesh& cpu, const Mesh& gpu) {
  ASSERT_EQ(cpu.vertexCount(), gpu.vertexCount());
  ASSERT_EQ(cpu.faceCount(), gpu.faceCount());
  const CanonicalMesh a = canonical(cpu), b = canonical(gpu);
  for (std::size_t v = 0; v < a.positions.size(); ++v)
    for (int k = 0; k < 3; ++k) ASSERT_NEAR(a.positions[v][k], b.positions[v][k], 1e-5) << "vertex " << v;
  EXPECT_TRUE(a.triangles == b.triangles);
}

// The same mesh in the same numbering (one path, two ways of reading the field).
inline void expectIdenticalMesh(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.vertexCount(), b.vertexCount());
  ASSERT_EQ(a.faceCount(), b.faceCount());
  for (std::size_t v = 0; v < a.vertexCount(); ++v)
    for (int k = 0; k < 3; ++k) ASSERT_NEAR(a.positions[v][k], b.positions[v][k], 1e-5) << "vertex " << v;
  EXPECT_TRUE(a.faceVertices == b.faceVertices);
}

}  // namespace isoatlas::extract::test_mesh
