// makeAtlas: the dense surface sampled into one chart per tile and packed (atlas.h).
//   dense        the dense triangle mesh the base mesh parametrises
//   base         the base mesh with its tiles (pairTriangles) and the parametrisation of `dense`
//   chartSize    N, texels per chart side: 2^k + 1 (multires::isChartSize)
// Every texel is the dense surface at its chart point through the parametrisation
// (multires::DenseSampler); where a folded image holds the point the nearest unfolded one answers,
// and the texel is counted as folded; where none holds it (a gap) the nearest does. Normals interpolate the dense mesh's area-weighted vertex
// normals. Then the shared borders: each base edge's N samples are averaged over the charts
// sharing it (see averageSharedBorders in the .cpp for samples that disagree) and written into each of them, and every chart corner is its base vertex (its normal
// averaged over the charts meeting there), so neighbouring charts agree bit for bit on their border.
// Throws Error(BadInput) for a chart size that is not 2^k + 1 or a base mesh without tiles.
#pragma once
#include <cstdint>

#include "atlas/atlas.h"
#include "core/mesh.h"
#include "multires/base_mesh.h"

namespace isoatlas::atlas {

struct ChartStats {
  std::uint64_t texels = 0;        // sampled (charts x N x N)
  std::uint64_t foldedTexels = 0;  // where a folded image held the point
  std::uint64_t gapTexels = 0;     // where no image held it (the nearest answered)
  std::uint64_t sharedSides = 0;   // tile sides averaged with a neighbour's
  std::uint64_t borderDisagreements = 0;  // shared samples from different sheets (one taken, not the mean)
  double seconds = 0;
};

Atlas makeAtlas(const Mesh& dense, const multires::BaseMesh& base, std::uint32_t chartSize, ChartStats* stats = nullptr);

}  // namespace isoatlas::atlas
