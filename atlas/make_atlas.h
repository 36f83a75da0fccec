// makeAtlas: the dense surface sampled into one chart per tile and packed (atlas.h).
//   dense        the dense triangle mesh the base mesh parametrises
//   base         the base mesh with its tiles (pairTriangles) and the parametrisation of `dense`
//   chartSize    N, texels per chart side: 2^k + 1 (multires::isChartSize)
//   relaxSweeps  how far the texels are moved over their tile to follow the surface's bending
//                (relax_chart.h), after which the finest ones are drawn onto the dense vertices the
//                grid misses (snap_texels.h); 0: the tile's uniform grid, the paper's
// Every texel is the dense surface at its chart point through the parametrisation's history
// (multires::ParametrisationHistory: exact, one-to-one and onto); normals interpolate the dense
// mesh's area-weighted vertex normals; triangleFaceNormals the normals of the dense faces under the
// finest level's triangles (atlas.h). Then the shared borders: each base edge's N samples are
// averaged over the charts sharing it (they agree within rounding; see averageSharedBorders in the
// .cpp for samples that do not) and written into each of them, and every chart corner is its base
// vertex (its normal averaged over the charts meeting there), so neighbouring charts agree bit for
// bit on their border. Throws Error(BadInput) for a chart size that is not 2^k + 1, a base mesh
// without tiles, or one without its parametrisation's history (read from a model file).
#pragma once
#include <cstdint>

#include "atlas/atlas.h"
#include "core/mesh.h"
#include "multires/base_mesh.h"

namespace isoatlas::atlas {

struct ChartStats {
  std::uint64_t texels = 0;        // sampled (charts x N x N)
  std::uint64_t coincidentTexels = 0;  // landing exactly where another texel of their chart lands (a broken record would)
  std::uint64_t gapTexels = 0;     // found outside a step's ring by more than rounding, sent to the nearest face
  std::uint64_t turnedTexelQuads = 0;  // texel quads turning against the surface by their first corner, as sampled (before the borders are averaged; atlas/backfacing_quads.h measures the final atlas as drawn)
  std::uint64_t nonConvexChartQuads = 0;  // texel quads whose chart points are not strictly convex (0 expected)
  std::uint64_t snappedTexels = 0;  // texels moved onto a dense vertex their grid missed (snap_texels.h)
  std::uint64_t unturnedTexels = 0;  // texels moved where fewer triangles round them face backwards (unturn_texels.h)
  std::uint64_t levelTwoCentresMoved = 0;  // charts whose centre moved so that level 2 lies nearer (relax_chart.h)
  std::uint64_t keptDiagonals = 0;  // charts whose diagonal runs along dense edges, its texels kept on it (ChartRelaxing::keepDiagonal)
  double meanHistorySteps = 0;     // the steps a texel walked back through the history
  std::uint64_t sharedSides = 0;   // tile sides averaged with a neighbour's
  std::uint64_t borderDisagreements = 0;  // shared samples from different sheets (one taken, not the mean)
  double seconds = 0;
};

inline constexpr int kDefaultRelaxSweeps = 8;
Atlas makeAtlas(const Mesh& dense, const multires::BaseMesh& base, std::uint32_t chartSize, ChartStats* stats = nullptr,
                int relaxSweeps = kDefaultRelaxSweeps);

}  // namespace isoatlas::atlas
