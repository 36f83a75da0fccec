// Distances between triangle meshes: closest-point queries through a hashed uniform grid, and the
// symmetric Hausdorff distance sampled as Metro does (every vertex plus points spread evenly over
// the faces of each mesh, measured to the other surface). PSNR = 20 log10(diagonal / Hausdorff).
#pragma once
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/mesh.h"

namespace isoatlas::multires {

class TriangleGrid {
public:
  explicit TriangleGrid(const Mesh& mesh);  // keeps a reference; triangles only
  // Distance from p to the nearest triangle.
  double distance(const Vec3& p) const;

private:
  std::int64_t cellOf(double x, int axis) const;
  std::uint64_t key(std::int64_t x, std::int64_t y, std::int64_t z) const;
  const Mesh& mesh_;
  Vec3 origin_;
  double cell_ = 1;
  std::int64_t extent_[3]{};
  std::unordered_map<std::uint64_t, std::uint32_t> cellIndex_;
  std::vector<std::uint32_t> offsets_, triangles_;
};

// The points Metro-style sampling measures: the vertices, and about `facePoints` points spread over
// the faces in proportion to their area.
std::vector<Vec3> surfaceSamples(const Mesh& mesh, std::size_t facePoints);

struct Hausdorff {
  double aToB = 0, bToA = 0;  // largest distance from a sample of one mesh to the other surface
  double meanAToB = 0, meanBToA = 0;
  double symmetric() const { return aToB > bToA ? aToB : bToA; }
};
// Samples each mesh with its vertices plus max(2 x the larger vertex count, 100000) face points.
Hausdorff hausdorffDistance(const Mesh& a, const Mesh& b);

// 20 log10(diagonal / distance); infinite for a zero distance.
double psnrDb(double diagonal, double distance);

}  // namespace isoatlas::multires
