// snapTexels: a chart's finest texels drawn onto the dense vertices its grid misses. A dense vertex
// between texels (the tip of a narrow protrusion, a crease the parametrisation squeezes) is cut off by
// the finest level's triangles; the relaxation (relax_chart.h) measures the bending at the texels
// and cannot see a feature narrower than their spacing, and such places set the largest distance.
//
// A dense vertex's error is its distance from the finest level's surface at its own chart point
// (the level's triangles are linear in the chart: reconstruct.h's grid and diagonals). Worst first,
// one corner of the grid square holding it moves onto its chart point, so that its sample is the
// vertex, when:
//   - the corner is new at the finest two levels (i or j odd: the coarser levels keep their
//     texels) and not on the chart's border (shared with the chart across);
//   - the four squares around it stay strictly convex (exact predicates), so the grid still embeds
//     the tile and the texels keep the parametrisation's one-to-one map;
//   - the largest error of the dense vertices in those four squares falls (their union does not
//     change, so no vertex enters or leaves it), and the level's triangles at the texel do not
//     stray from the surface by as much as that error was (measured at their centroids and the
//     middles of their edges at the texel, against the surface at the same chart points): a texel
//     drawn off a crease must not make the triangles beside it cut across the crease.
// Each texel moves at most once, and never onto a neighbour's place as the atlas stores it (floats);
// errors below a billionth of the chart's extent are left.
//   n          texels a side (2^k + 1); q the chart points, texel (i, j) at j * n + i, strictly
//              convex squares; p their surface points. Both are updated.
//   vertices   the dense vertices inside the tile: chart point (in (0, 1)^2) and position
//   surfaceAt  the surface at a chart point, through the parametrisation
//   keepDiagonal  the texels on the tile's diagonal (i == j) stay (ChartRelaxing::keepDiagonal)
// Returns how many texels moved.
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "atlas/chart_grid.h"
#include "core/vec.h"
#include "multires/vec2.h"

namespace isoatlas::atlas {

std::uint32_t snapTexels(std::uint32_t n, std::span<const ChartVertex> vertices,
                         const std::function<Vec3(const multires::Vec2&)>& surfaceAt, std::vector<multires::Vec2>& q,
                         std::vector<Vec3>& p, bool keepDiagonal = false);

}  // namespace isoatlas::atlas
