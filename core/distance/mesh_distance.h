// The one module every distance isoatlas reports comes from (core/distance: below multires and atlas,
// so both, the pipeline and the benchmarks measure with it), on CGAL.
// hausdorffDistance: the approximate Hausdorff distance between two triangle meshes, both ways, as
// CGAL's Polygon_mesh_processing::approximate_Hausdorff_distance measures it, taken apart so that one
// side's samples and tree serve many measures (the one yardstick of every Hausdorff and PSNR figure
// isoatlas reports, so that its models and CGAL's simplifier are judged alike): each mesh is sampled
// at its vertices plus `facePoints` points spread at random (seed 0, so a figure repeats) over its
// faces in proportion to their area, and each sample measured to the other surface by CGAL's
// projection onto its nearest triangle (triangle_tree.h). The samples are CGAL's sample_triangle_mesh
// points; on an oriented manifold they are drawn as from a soup of triangles (CGAL's
// sample_triangle_soup, its areas computed in parallel), the same points without the halfedges.
// tests/core/mesh_distance_cgal_test.cpp holds both ways to CGAL's own figure, bit for bit. The root
// mean square of the same distances is Multi-chart Geometry Images' measure.
//   a, b        triangle meshes (faces of three corners; others refused)
//   facePoints  face samples per mesh
// PSNR = 20 log10(diagonal / distance), the diagonal that of the dense mesh's bounding box.
#pragma once
#include <cstddef>
#include <memory>

#include "core/mesh.h"
#include "core/mesh_topology.h"

namespace isoatlas {

inline constexpr std::size_t kHausdorffFacePoints = 200000;

struct Hausdorff {
  double aToB = 0, bToA = 0;  // farthest sample of one mesh from the other surface
  double rmsAToB = 0, rmsBToA = 0;  // root mean square of the same samples' distances
  double symmetric() const { return aToB > bToA ? aToB : bToA; }
  double rms() const { return rmsAToB > rmsBToA ? rmsAToB : rmsBToA; }
};
Hausdorff hausdorffDistance(const Mesh& a, const Mesh& b, std::size_t facePoints = kHausdorffFacePoints);

// One mesh measured against many (eval's levels against the dense mesh): its samples are drawn and
// its AABB tree built once. to(b) gives what hausdorffDistance(a, b, facePoints) gives.
class MeshDistances {
public:
  MeshDistances(const Mesh& a, std::size_t facePoints = kHausdorffFacePoints);
  ~MeshDistances();
  // b's topology is analysed on the way (it tells whether CGAL may sample b as a soup of triangles,
  // without building its halfedges): topologyOfB, when given, receives analyzeTopology(b).
  Hausdorff to(const Mesh& b, MeshTopology* topologyOfB = nullptr) const;

private:
  struct State;
  std::unique_ptr<State> state_;
};

// 20 log10(diagonal / distance); infinite for a zero distance.
double psnrDb(double diagonal, double distance);

}  // namespace isoatlas
