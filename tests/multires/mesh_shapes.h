// Small triangle meshes of known topology for the multiresolution tests: a torus and a sphere from
// parametric grids, a plane with square holes, and a double torus from marching cubes.
#pragma once
#include <cmath>
#include <numbers>

#include "core/mesh.h"
#include "core/volume.h"
#include "extract/extract_surface.h"
#include "tests/test_util.h"

namespace isoatlas::test {

// Torus of radii R, r with n x m quads, each split into two triangles (genus 1, closed).
inline Mesh torusMesh(int n, int m, double R = 3, double r = 1) {
  Mesh mesh;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * std::numbers::pi * i / n, v = 2 * std::numbers::pi * j / m;
      mesh.positions.push_back({(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
    }
  auto id = [&](int i, int j) { return std::uint32_t(((i + n) % n) * m + (j + m) % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      mesh.addFace({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.addFace({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return mesh;
}

// A w x h grid of unit squares in the z = f(x, y) plane, without the squares whose (i, j) `hole`
// returns true (each such block of squares leaves a boundary loop).
template <class Hole>
Mesh gridMesh(int w, int h, Hole hole) {
  Mesh mesh;
  for (int j = 0; j <= h; ++j)
    for (int i = 0; i <= w; ++i)
      mesh.positions.push_back({double(i), double(j), 0.3 * std::sin(0.4 * i) * std::cos(0.3 * j)});
  auto id = [&](int i, int j) { return std::uint32_t(j * (w + 1) + i); };
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      if (hole(i, j)) continue;
      mesh.addFace({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.addFace({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return dropUnusedVertices(mesh);  // the vertices inside holes
}

// Marching cubes of an implicit function sampled on a grid (positive inside).
template <class F>
Mesh implicitMesh(std::array<std::int64_t, 3> dims, F f) {
  return extract::extractSurface(fieldVolume(dims, f), {.iso = 0.0f});
}

inline Mesh sphereMesh(double radius = 10) {
  const double c = radius + 2.3;
  const int n = int(2 * radius + 6);
  return implicitMesh({n, n, n}, [&](double x, double y, double z) {
    return radius - std::sqrt((x - c) * (x - c) + (y - c - 0.2) * (y - c - 0.2) + (z - c + 0.1) * (z - c + 0.1));
  });
}

// Two tori side by side, fused: genus 2.
inline Mesh doubleTorusMesh() {
  auto torus = [](double x, double y, double z, double cx) {
    const double q = std::sqrt((x - cx) * (x - cx) + (y - 14) * (y - 14)) - 7;
    return 3.2 - std::sqrt(q * q + (z - 7) * (z - 7));
  };
  return implicitMesh({48, 28, 14}, [&](double x, double y, double z) {
    return std::max(torus(x, y, z, 14.2), torus(x, y, z, 32.7));
  });
}

// Three tori in a row, fused: genus 3.
inline Mesh tripleTorusMesh() {
  auto torus = [](double x, double y, double z, double cx) {
    const double q = std::sqrt((x - cx) * (x - cx) + (y - 12) * (y - 12)) - 6;
    return 2.8 - std::sqrt(q * q + (z - 6) * (z - 6));
  };
  return implicitMesh({62, 24, 12}, [&](double x, double y, double z) {
    return std::max({torus(x, y, z, 12), torus(x, y, z, 28.5), torus(x, y, z, 45)});
  });
}

// A hollow ball whose wall is 1.2 voxels thick (marching cubes of a thin shell): two sheets close
// together, joined by tunnels where the wall falls between the samples, where a parametrisation that
// folds samples the wrong sheet.
inline Mesh thinShellMesh() {
  return implicitMesh({24, 24, 24}, [](double x, double y, double z) {
    const double r = std::sqrt((x - 11.6) * (x - 11.6) + (y - 11.8) * (y - 11.8) + (z - 11.3) * (z - 11.3));
    return 0.6 - std::abs(r - 8.4);
  });
}

}  // namespace isoatlas::test
