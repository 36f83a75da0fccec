// AdaptiveMesh: the paper's specialised halfedge (section 4.3) over the triquad base mesh, driving
// adaptive refinement with stellar edge splits and edge welds on the CPU.
//   - Each face points to its interior halfedge (the tile's diagonal at the base; after a split, the
//     edge opposite the new vertex); every other halfedge is a tile border. An edge can be split when
//     both its halfedges are interior (or its one halfedge, on the mesh boundary); a vertex can be
//     welded when none of its halfedges is interior (the 4-8 refinement rules).
//   - Each halfedge stores the chart (tile) of its face and its start and end (u, v) on that chart, in
//     texels of a chart of `chartSize` (2^k + 1) texels per side; so a split can go no finer than the
//     chart's texels.
//   - Each vertex stores its resolution level (0 for base vertices) in 7 bits, and for odd levels
//     (the centre of a square of the chart) which diagonal it was split from in the eighth.
// refine() makes the forced splits first, so neighbouring faces never differ by more than one level.
// New vertices are sampled at the split point from the chart, through a callback; on a tile side,
// from the chart of lower index.
#pragma once
#include <functional>
#include <optional>

#include "multires/base_mesh.h"
#include "multires/stellar_mesh.h"

namespace isoatlas::multires {

struct ChartPoint {
  std::uint32_t chart;  // tile index
  double u, v;          // in [0, 1]
};

// The patches the GPU draws (the paper's Fig. 7): a square of a chart, lower-left corner (u, v) and
// side s in texels, and c, the finest vertex level inside it (its tessellation starts there).
struct Patch {
  std::uint32_t chart;
  std::uint16_t u, v, s;
  std::uint8_t c;
};

class AdaptiveMesh {
public:
  using Sampler = std::function<Vec3(const ChartPoint&)>;
  // Tile i is chart i: its quad (p, s, q, r), with the shared edge p -> q of its first triangle,
  // maps to (0,0), (1,0), (1,1), (0,1). Throws Error(BadInput) for a chart size that is not
  // isChartSize, or a base mesh without tiles.
  AdaptiveMesh(const BaseMesh& base, std::uint32_t chartSize, Sampler sampler);

  bool canSplit(EdgeH e) const;
  bool canWeld(VertexH v) const;
  VertexH split(EdgeH e);  // requires canSplit
  void weld(VertexH v);    // requires canWeld
  // The ends of the edge whose split made v (what a weld of v joins again); requires canWeld(v).
  std::array<VertexH, 2> weldParents(VertexH v) const;
  // Splits e after the splits that conformity forces; false when that would go finer than the chart.
  bool refine(EdgeH e);
  // Where a split of e would put its vertex (the chart's sample at the edge's midpoint, from the
  // chart of lower index on a tile side), without splitting; nullopt when the midpoint falls between
  // the chart's texels.
  std::optional<Vec3> splitPosition(EdgeH e) const;

  int level(VertexH v) const;
  bool isInterior(HalfedgeH h) const;
  const StellarMesh& mesh() const { return mesh_; }
  // Drops the elements welds deleted and renumbers the rest (OpenMesh's garbage collection, keeping
  // the faces' interior halfedges pointing right).
  void compact();
  std::uint32_t chartSize() const { return chartSize_; }
  std::uint32_t chart(HalfedgeH h) const;
  std::array<int, 4> uv(HalfedgeH h) const;  // start u, v and end u, v in texels

  std::vector<Patch> patches() const;
  Mesh triangles() const { return toMesh(mesh_); }

  // Storage of the specialised halfedge, as the paper counts it (it gives 6 and 1).
  static constexpr std::size_t kBytesPerHalfedge = 4 + 4;  // chart index (u32) + start, end uv (4 x u8)
  static constexpr std::size_t kBytesPerVertex = 1;        // level and diagonal bit
  static constexpr std::size_t kBytesPerFace = 4;          // its interior halfedge

private:
  int faceLevel(FaceH f) const;
  void setFace(FaceH f, std::uint32_t chart, const std::vector<std::pair<int, std::array<int, 2>>>& uvOf);

  StellarMesh mesh_;
  std::uint32_t chartSize_, charts_;
  Sampler sampler_;
  OpenMesh::HPropHandleT<std::uint32_t> chart_;
  OpenMesh::HPropHandleT<std::array<std::uint8_t, 4>> uv_;
  OpenMesh::FPropHandleT<HalfedgeH> interior_;
  OpenMesh::VPropHandleT<std::uint8_t> level_;
};

}  // namespace isoatlas::multires
