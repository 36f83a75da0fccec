// unturnTexels: a chart's finest texels moved where fewer of the finest level's triangles round them
// fold: face against the dense face under their centroid (countFoldedQuads' test, backfacing_quads.h).
// A triangle between three texels folds where its texels land on the surface out of the order their
// chart points have (a hard shear of the parametrisation, or the relaxation and the snapping pulling
// texels up to a crease from both sides): a hole under back-face culling, a dark line under two-sided
// shading.
// Each texel off the border with such a triangle round it tries, in sweeps, places in the chart: the
// middle of its four neighbours, its place on the tile's uniform grid, and a 5 x 5 lattice over half
// the box of its neighbours; every texel off the border moves, those of the coarser levels too (kept
// to the finest two levels, i or j odd, it left 38 % more folds on bunny00, femur and cow: 5,961
// against 4,327; bench/RESULTS.md, "Folds"). A place is taken, the fewest folded and then the least
// error first, when the four squares round the texel stay strictly convex (exact predicates: the grid still embeds
// the tile), fewer of their triangles fold, and the squares' error (the largest distance of the dense
// vertices in them from the level, and the stray of the texel's triangles, as snap_texels.h measures
// them) is no larger than before. Judged by the shading normals at the corners instead, it halved
// the quads facing against them over 70 meshes of the corpus (median 0.81 % to 0.44 %); by the faces
// under the centroids it lowers the folds further (bench/RESULTS.md, "Folds").
//   n          texels a side (2^k + 1); q the chart points, texel (i, j) at j * n + i, strictly convex
//              squares; p their surface points. Both are updated.
//   vertices   the dense vertices inside the tile: chart point (in (0, 1)^2) and position
//   surfaceAt  the surface at a chart point, through the parametrisation, and the unit normal of the
//              dense face there
//   keepDiagonal  the texels on the tile's diagonal (i == j) stay (ChartRelaxing::keepDiagonal)
// Returns how many texels moved.
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "atlas/chart_grid.h"
#include "atlas/relax_chart.h"
#include "core/vec.h"
#include "multires/vec2.h"

namespace isoatlas::atlas {

std::uint32_t unturnTexels(std::uint32_t n, std::span<const ChartVertex> vertices,
                           const std::function<SurfacePoint(const multires::Vec2&)>& surfaceAt, std::vector<multires::Vec2>& q,
                           std::vector<Vec3>& p, bool keepDiagonal = false);

}  // namespace isoatlas::atlas
