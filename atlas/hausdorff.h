// hausdorffDistance: the approximate Hausdorff distance between two triangle meshes, both ways, by
// CGAL's Polygon_mesh_processing::approximate_Hausdorff_distance (the one yardstick of every
// Hausdorff and PSNR figure isoatlas reports, so that its models and CGAL's simplifier are judged
// alike). Each mesh is sampled at its vertices plus `facePoints` points spread at random (seed 0,
// so a figure repeats) over its faces in proportion to their area, and each sample measured to the
// other surface. Keeps CGAL's headers in this one translation unit.
//   a, b        triangle meshes (faces of three corners; others refused)
//   facePoints  face samples per mesh
// PSNR = 20 log10(diagonal / distance), the diagonal that of the dense mesh's bounding box.
#pragma once
#include <cstddef>

#include "core/mesh.h"

namespace isoatlas::atlas {

inline constexpr std::size_t kHausdorffFacePoints = 200000;

struct Hausdorff {
  double aToB = 0, bToA = 0;  // farthest sample of one mesh from the other surface
  double symmetric() const { return aToB > bToA ? aToB : bToA; }
};
Hausdorff hausdorffDistance(const Mesh& a, const Mesh& b, std::size_t facePoints = kHausdorffFacePoints);

// 20 log10(diagonal / distance); infinite for a zero distance.
double psnrDb(double diagonal, double distance);

}  // namespace isoatlas::atlas
