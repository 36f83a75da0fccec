// BaseMesh: what simplification hands on. The coarse triangles (every base vertex an original dense
// vertex, or a vertex added by an edge split), the parametrisation of the dense mesh over them (each
// dense vertex: a base triangle and barycentric coordinates in it) and, once paired, the tiles.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/mesh.h"
#include "multires/parametrisation_history.h"

namespace isoatlas::multires {

// Chart sizes a tile's chart can have: 2^k + 1 texels a side, whose last texel index (size - 1)
// fits the adaptive mesh's 8-bit (u, v) per halfedge: 3 .. 129.
inline constexpr std::uint32_t kMaxChartSize = 129;
constexpr bool isChartSize(std::uint32_t size) {
  return size >= 3 && size <= kMaxChartSize && ((size - 1) & (size - 2)) == 0;
}

struct BaseMesh {
  std::vector<Vec3> positions;
  std::vector<std::int64_t> denseVertex;  // per base vertex: its dense vertex, or -1 when made by a split
  std::vector<std::array<std::uint32_t, 3>> triangles;  // counter-clockwise, as the dense faces

  // Dense vertex i lies in base triangle denseTriangle[i] at weights denseBary[i] of that triangle's
  // corners (non-negative, summing to one).
  std::vector<std::uint32_t> denseTriangle;
  std::vector<std::array<double, 3>> denseBary;

  // The exact map the other way, from the base mesh to the dense mesh (stellar simplification records
  // it): base triangle t lies in historyFrames[t] of `history`. Charts sample the dense surface
  // through it. Empty for a base mesh read from a model file.
  std::shared_ptr<const ParametrisationHistory> history;
  std::vector<HistoryFrame> historyFrames;
  // The dense surface at base point (triangle, bary), through the history (which must be there).
  ParametrisationHistory::DensePoint densePoint(std::uint32_t triangle, const std::array<double, 3>& bary,
                                                ParametrisationHistory::Hints* hints = nullptr) const {
    return history->toDense(historyFrames[triangle].version, historyFrames[triangle].toVersion(bary), hints);
  }

  // Filled by pairTriangles: each tile is two triangles sharing an edge; every triangle is in one.
  std::vector<std::array<std::uint32_t, 2>> tiles;

  std::size_t vertexCount() const { return positions.size(); }
  std::size_t triangleCount() const { return triangles.size(); }
  Vec3 pointAt(std::uint32_t triangle, const std::array<double, 3>& bary) const {
    const auto& t = triangles[triangle];
    return positions[t[0]] * bary[0] + positions[t[1]] * bary[1] + positions[t[2]] * bary[2];
  }
  // Tile i as a quad (p, s, q, r), counter-clockwise: its first triangle is (p, q, r) with the shared
  // edge p -> q starting at corner `first`, its second (q, p, s) starting at corner `second`.
  struct TileCorners {
    std::uint32_t p, s, q, r;
    int first, second;
  };
  TileCorners tileCorners(std::uint32_t tile) const;
  // Tile i's chart is the unit square on its quad (p, s, q, r), where p -> q is the edge its first
  // triangle shares: p (0,0), s (1,0), q (1,1), r (0,1). Returns the base triangle and barycentric
  // coordinates of chart point (u, v).
  std::pair<std::uint32_t, std::array<double, 3>> chartToTriangle(std::uint32_t tile, double u, double v) const;
  // The other way: the chart point (u, v) of tile `tile` at weights `bary` of its triangle
  // `triangle` (one of tiles[tile]).
  std::array<double, 2> triangleToChart(std::uint32_t tile, std::uint32_t triangle, const std::array<double, 3>& bary) const;
  // Per triangle t and edge e (corner e to corner e + 1): the triangle across it, or kNoTriangle on
  // the boundary.
  static constexpr std::uint32_t kNoTriangle = isoatlas::kNoTriangle;  // core/mesh.h's triangleNeighbours
  std::vector<std::array<std::uint32_t, 3>> triangleNeighbours() const;
  Mesh triangleMesh() const;  // the base triangles as a Mesh
  Mesh quadMesh() const;      // the tiles as quads (the shared edge dropped); requires tiles
};

}  // namespace isoatlas::multires
