// makeAtlas: the dense surface sampled into one chart per tile and packed (atlas.h).
//   dense        the dense triangle mesh the base mesh parametrises
//   base         the base mesh with its tiles (pairTriangles) and the parametrisation of `dense`
//   chartSize    N, texels per chart side: 2^k + 1 (multires::isChartSize)
// Every texel is the dense surface at its chart point through the parametrisation
// (multires::DenseSampler); where a folded image holds the point the nearest unfolded one answers,
// and the texel is counted as folded; where none holds it (a gap) the nearest does. Normals interpolate the dense mesh's area-weighted vertex
// normals. Texels the parametrisation sent to a distant sheet are put back (repairOutliers). Then
// the shared borders: each base edge's N samples are averaged over the charts
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
  std::uint64_t repairedTexels = 0;  // far from all their chart neighbours: refilled, put back on the surface
  std::uint64_t sharedSides = 0;   // tile sides averaged with a neighbour's
  std::uint64_t borderDisagreements = 0;  // shared samples from different sheets (one taken, not the mean)
  double seconds = 0;
};

Atlas makeAtlas(const Mesh& dense, const multires::BaseMesh& base, std::uint32_t chartSize, ChartStats* stats = nullptr);

// The step of makeAtlas between sampling and the borders: chart texels far from all their chart
// neighbours (more than 4 times the chart's median texel spacing from the nearest, and 4 times
// their spread from their mean), where the parametrisation sent one place of a chart to a distant
// sheet of the surface, are refilled from their neighbours (Laplace's averaging) and put back on
// the dense surface at its nearest point (CGAL's AABB tree), their normal interpolated there.
// normals: vertexNormals(dense); held: per atlas texel, set for the refilled ones. Returns their count.
std::uint64_t repairOutliers(const Mesh& dense, const std::vector<Vec3>& normals, Atlas& atlas, std::vector<std::uint8_t>& held);

}  // namespace isoatlas::atlas
