// Where a chart's texels sit in its tile. Sampled at the tile's uniform grid, texels crowd where the
// parametrisation squeezes the surface and thin out where it stretches it (around creases, along the
// tile's diagonal where its two triangles meet), and the largest distance to the surface is set
// there. These move them so that each texel spacing covers about as much of the surface's bending
// (spacing ~ 1 / sqrt(curvature + flatCurvature) on the surface: the interpolation error of a
// spacing h is about curvature * h^2, evened out), keeping the grid an embedding of the tile, so
// the texels keep the parametrisation's one-to-one map.
//
// The curvature of a texel spacing is |n_a - n_b| / |p_a - p_b| between its texels (unit normals).
// flatCurvature is the floor that keeps flat parts sampled (spacing there ~ 1/sqrt(flatCurvature)):
// e.g. a typical curvature of the dense surface.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include "atlas/chart_grid.h"
#include "core/vec.h"
#include "multires/vec2.h"

namespace isoatlas::atlas {

struct SurfacePoint {
  Vec3 position, normal;  // the normal of unit length
};

struct ChartRelaxing {
  int sweeps = 0;             // on the grids of 5 and 9 a side, half as many on each finer one (at least 1); 0: the tile's uniform grid
  double flatCurvature = 1;   // per unit of length, > 0
  // The texels of this coarser grid (2^k + 1) stay on the tile's uniform grid: 3, its corners and
  // centre, but for levelTwoGuard below (5 kept levels 0-4's texels uniform: the levels above gained
  // 0.5 to 2.4 dB at level 10 from relaxing them too; bench/RESULTS.md).
  std::uint32_t keptSize = 3;
  // The texels on the tile's diagonal (i == j, where its two base triangles meet) stay on it, moving
  // only along it: for a tile whose diagonal runs along dense edges (make_atlas.cpp), a crease that
  // the levels' triangles, cut along that diagonal, then keep at every level.
  bool keepDiagonal = false;
  // Level 2 (the grid of 3) can lie farther from the surface than level 0 where its new texels land
  // on crests either side of a fold that level 0's flat triangles cut across. Where the grid of 3
  // lies farther from the surface than the tile's corners alone (levelError, both ways) and farther
  // than this, its centre texel moves to the candidate place where it lies nearest (a 7 x 7 lattice
  // over the middle half of the tile, its four squares strictly convex). The centre stays in every
  // finer grid, so it moves only where level 2 could set the model's largest distance (make_atlas.cpp
  // passes a share of level 0's largest over the tiles); infinity: never.
  double levelTwoGuard = std::numeric_limits<double>::infinity();
};

// uniformFractions: n texels at equal steps along a side, 0 to 1.
std::vector<double> uniformFractions(std::uint32_t n);

// relaxSide: where n texels sit along one tile side, as fractions from its first end (0 and 1 at
// the ends, strictly increasing), so that each spacing covers the same bending of the surface.
//   surfaceAt  the surface at fraction t of the side
// A side is shared by two charts: compute it once and give both the same fractions (one reversed).
std::vector<double> relaxSide(std::uint32_t n, const std::function<SurfacePoint(double)>& surfaceAt, const ChartRelaxing& how);

// levelError: how far the level of grid q (n a side, each square cut as reconstructLevel cuts it)
// lies from the surface, both ways: the largest distance between a point of its triangles (each
// triangle's centroid, each edge's middle) and the surface at that point's chart point, and the dense
// `vertices`' largest distance from it at their chart points.
double levelError(std::uint32_t n, const std::vector<multires::Vec2>& q,
                  const std::function<SurfacePoint(const multires::Vec2&)>& surfaceAt, std::span<const ChartVertex> vertices);

// The grid of 2 a side: the tile's corners, texel (i, j) at j * 2 + i. levelZeroError: how far
// level 0 (the tile's two base triangles) lies from the surface, as levelError measures the grid of 2.
std::vector<multires::Vec2> tileCorners();
double levelZeroError(const std::function<SurfacePoint(const multires::Vec2&)>& surfaceAt, std::span<const ChartVertex> vertices);

// levelTwoCentreMoved: whether relaxChart's points q (n a side) have the grid of 3's centre off the
// crossing of the sides' middles, (0.5, 0.5), where the sides keep them: only levelTwoGuard moves it.
bool levelTwoCentreMoved(std::uint32_t n, const std::vector<multires::Vec2>& q);

// coarsestRelaxedError: how far the coarsest grid relaxChart relaxes (every (stride / 2)-th texel
// of the kept grid's, 5 a side by default), spanned by its sides alone, lies from the surface (its
// triangles' stray and the dense vertices' distance, as relaxChart judges that grid), with tile side
// `side` at `fractions` (n of them, relaxSide's) and the others uniform. A side's fractions are kept
// only where this is no worse on the charts on both sides than with the coarsest grid's texels
// uniform (make_atlas.cpp): relaxing a side by its own bending alone can pull that grid's triangles
// across a crease beside it.
double coarsestRelaxedError(std::uint32_t n, int side, const std::vector<double>& fractions,
                            const std::function<SurfacePoint(const multires::Vec2&)>& surfaceAt, const ChartRelaxing& how,
                            std::span<const ChartVertex> vertices);

// relaxChart: the n x n chart points of a tile, texel (i, j) at j * n + i, in [0, 1]^2.
//   surfaceAt  the surface at chart point (u, v), through the parametrisation
//   sides      per side (tile_sides.h's order and direction), its n fractions (relaxSide); the
//              border texels stay there, so neighbouring charts still sample their shared side alike
// Coarse to fine, as the model's levels take the texels: from the tile's corners, each grid is
// refined to the next (refineChartGrid), its border at the sides' fractions. Up to the grid of
// keptSize a side that is all (with sweeps 0, up to the chart's: uniform sides give the tile's
// uniform grid), but for the grid of 3's centre, which moves where how.levelTwoGuard says. On each
// finer grid (9, 17, .. a side) each sweep moves every new texel towards the mean of its four
// neighbours on the surface, weighted by each spacing's sqrt(curvature + flatCurvature) (that step
// taken into the chart through the grid's local derivative, halved), and takes a move only where no
// quad around the texel stops being strictly convex and counter-clockwise in the chart (exact
// predicates). The coarsest grid relaxed (5 a side by default)
// spans the tile with few texels, where the bending at them can pull its triangles across a crease:
// it keeps its relaxed places only where its level lies no farther from the surface (levelError, with
// the tile's dense `vertices`) than as its sides span it. Returns the points and, in nonConvex, how
// many quads are not strictly convex at the end (0 whenever the sides rise from 0 to 1).
std::vector<multires::Vec2> relaxChart(std::uint32_t n, const std::function<SurfacePoint(const multires::Vec2&)>& surfaceAt,
                                       const std::array<std::vector<double>, 4>& sides, const ChartRelaxing& how,
                                       std::uint32_t* nonConvex = nullptr, std::span<const ChartVertex> vertices = {});

// refineChartGrid: grid q (n a side, texel (i, j) at j * n + i) refined to 2n - 1 a side, as
// relaxChart refines: the old texels at the even places, new ones at the middles of its edges (the
// border's then at `sides`, of 2n - 1 fractions each), and in each quad where the lines between its
// opposite new edge texels cross. A strictly convex quad splits into four strictly convex ones
// (its corners' mean would not do where its sides' new texels were moved).
// With keepDiagonal, the new texels on the diagonal (i == j) go where it crosses the line between
// their quad's new edge texels above and below, so that a diagonal on the line u = v stays on it.
std::vector<multires::Vec2> refineChartGrid(std::uint32_t n, const std::vector<multires::Vec2>& q,
                                            const std::array<std::vector<double>, 4>& sides, bool keepDiagonal = false);

// convexChartQuad: whether the quad of texels (i, j) .. (i + 1, j + 1) of grid q (n a side) turns
// counter-clockwise at all four corners (exact predicates). convexAroundTexel: the four quads around
// interior texel (i, j), one bit each.
bool convexChartQuad(const std::vector<multires::Vec2>& q, std::uint32_t n, std::uint32_t i, std::uint32_t j);
unsigned convexAroundTexel(const std::vector<multires::Vec2>& q, std::uint32_t n, std::uint32_t i, std::uint32_t j);

}  // namespace isoatlas::atlas
