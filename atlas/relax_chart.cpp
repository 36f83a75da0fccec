#include "atlas/relax_chart.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "atlas/chart_grid.h"
#include "atlas/reconstruct.h"
#include "atlas/tile_sides.h"
#include "core/error.h"
#include "multires/exact_orientation.h"

namespace isoatlas::atlas {
namespace {

using multires::Vec2;

// How much a spacing between two surface points counts: its length weighted by the bending over it.
double spacingWeight(const SurfacePoint& a, const SurfacePoint& b, double flatCurvature) {
  const double length = norm(b.position - a.position);
  const double curvature = length > 0 ? norm(b.normal - a.normal) / length : 0;
  return std::sqrt(curvature + flatCurvature);
}

// The chart step that moves texel k's surface point towards `target`: the surface step written in
// the grid's two directions at k (least squares), then taken into the chart the same way.
bool chartStep(const std::vector<Vec2>& q, const std::vector<SurfacePoint>& p, std::uint32_t n, std::size_t k, const Vec3& target,
               Vec2& step) {
  const Vec3 a = p[k + 1].position - p[k - 1].position, b = p[k + n].position - p[k - n].position, d = target - p[k].position;
  const double aa = dot(a, a), ab = dot(a, b), bb = dot(b, b);
  const double det = aa * bb - ab * ab;
  if (!(det > 1e-12 * aa * bb)) return false;
  const double x = (bb * dot(a, d) - ab * dot(b, d)) / det, y = (aa * dot(b, d) - ab * dot(a, d)) / det;
  step = (q[k + 1] - q[k - 1]) * x + (q[k + n] - q[k - n]) * y;
  return true;
}

// The border texels of grid q (n a side) exactly at the sides' fractions.
void setBorder(std::uint32_t n, const std::array<std::vector<double>, 4>& sides, std::vector<Vec2>& q) {
  for (int s = 0; s < 4; ++s)
    for (std::uint32_t m = 0; m < n; ++m) {
      const auto ij = sideTexel(s, m, n);
      q[std::size_t(ij[1]) * n + ij[0]] = sidePoint(s, sides[std::size_t(s)][m]);
    }
}

// Texels on every stride-th line of a chart stay where the tile's uniform grid has them.
std::uint32_t keptStride(std::uint32_t n, const ChartRelaxing& how) {
  require(multires::isChartSize(n) && multires::isChartSize(how.keptSize), "relaxing a chart: sizes must be 2^k + 1");
  return how.keptSize >= n ? 1 : (n - 1) / (how.keptSize - 1);
}

// Sweeps of the weighted smoothing over the new texels of grid q (n a side; p its surface): those
// of the coarser grid it was refined from (i and j even) stay.
void smoothNewTexels(std::uint32_t n, const std::function<SurfacePoint(const Vec2&)>& surfaceAt, const ChartRelaxing& how, int sweeps,
                     std::vector<Vec2>& q, std::vector<SurfacePoint>& p) {
  for (int sweep = 0; sweep < sweeps; ++sweep)
    for (std::uint32_t j = 1; j + 1 < n; ++j)
      for (std::uint32_t i = 1; i + 1 < n; ++i) {
        if (i % 2 == 0 && j % 2 == 0) continue;
        const std::size_t k = std::size_t(j) * n + i;
        Vec3 target;
        double weights = 0;
        for (const std::size_t m : {k - 1, k + 1, k - n, k + n}) {
          const double w = spacingWeight(p[k], p[m], how.flatCurvature);
          target = target + p[m].position * w;
          weights += w;
        }
        Vec2 step;
        if (!(weights > 0) || !chartStep(q, p, n, k, target * (1 / weights), step)) continue;
        if (how.keepDiagonal && i == j) step.x = step.y = (step.x + step.y) / 2;  // along the diagonal
        const Vec2 from = q[k];
        const unsigned convexBefore = convexAroundTexel(q, n, i, j);
        bool moved = false;
        for (double scale = 0.5; scale > 0.05 && !moved; scale *= 0.5) {
          q[k] = from + step * scale;
          moved = (convexAroundTexel(q, n, i, j) & convexBefore) == convexBefore;
        }
        if (moved) p[k] = surfaceAt(q[k]);
        else q[k] = from;
      }
}

// Every other fraction of each side: the sides of a grid of (n + 1) / 2 a side.
std::array<std::vector<double>, 4> coarserSides(const std::array<std::vector<double>, 4>& sides) {
  std::array<std::vector<double>, 4> out;
  for (int s = 0; s < 4; ++s)
    for (std::size_t m = 0; m < sides[s].size(); m += 2) out[s].push_back(sides[s][m]);
  return out;
}

// The sides of every grid, from the chart's (`sides`, first) down to the tile's corners' (2 a side).
std::vector<std::array<std::vector<double>, 4>> sidesOfEveryGrid(const std::array<std::vector<double>, 4>& sides) {
  std::vector<std::array<std::vector<double>, 4>> grids{sides};
  while (grids.back()[0].size() > 2) grids.push_back(coarserSides(grids.back()));
  return grids;
}

// Where segment a-b crosses segment c-d (they cross inside a convex quad whose opposite sides hold them).
Vec2 crossing(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double across = cross2(b - a, d - c);
  return a + (b - a) * (cross2(c - a, d - c) / across);
}

// How far the level of grid q lies from the surface: its triangles' largest stray, and the dense
// vertices' largest distance from it.
double levelError(std::uint32_t n, const std::vector<Vec2>& q, const std::vector<SurfacePoint>& p,
                  const std::function<SurfacePoint(const Vec2&)>& surfaceAt, std::span<const ChartVertex> vertices) {
  std::vector<Vec3> positions(p.size());
  for (std::size_t k = 0; k < p.size(); ++k) positions[k] = p[k].position;
  const ChartGrid grid(n, q, positions);
  return std::max(grid.largestStray([&](const Vec2& x) { return surfaceAt(x).position; }), largestVertexError(grid, vertices));
}

}  // namespace

std::vector<Vec2> tileCorners() { return {{0, 0}, {1, 0}, {0, 1}, {1, 1}}; }

double levelError(std::uint32_t n, const std::vector<Vec2>& q, const std::function<SurfacePoint(const Vec2&)>& surfaceAt,
                  std::span<const ChartVertex> vertices) {
  std::vector<SurfacePoint> p(q.size());
  for (std::size_t k = 0; k < q.size(); ++k) p[k] = surfaceAt(q[k]);
  return levelError(n, q, p, surfaceAt, vertices);
}

double levelZeroError(const std::function<SurfacePoint(const Vec2&)>& surfaceAt, std::span<const ChartVertex> vertices) {
  return levelError(2, tileCorners(), surfaceAt, vertices);
}

bool levelTwoCentreMoved(std::uint32_t n, const std::vector<Vec2>& q) {
  const Vec2& centre = q[std::size_t(n / 2) * n + n / 2];
  return centre.x != 0.5 || centre.y != 0.5;
}

namespace {

// The grid of 3 (q, p its surface) with its centre moved where level 2 lies nearest the surface,
// when it lies farther than the tile's corners alone and than `guard` (ChartRelaxing::levelTwoGuard).
void placeLevelTwoCentre(std::vector<Vec2>& q, std::vector<SurfacePoint>& p, const std::function<SurfacePoint(const Vec2&)>& surfaceAt,
                         std::span<const ChartVertex> vertices, double guard, bool keepDiagonal) {
  double best = levelError(3, q, p, surfaceAt, vertices);
  if (!(best > guard) || !(best > levelZeroError(surfaceAt, vertices))) return;
  constexpr int kSteps = 8;  // candidates at the 7 x 7 inner points of a lattice over [0.25, 0.75]^2
  constexpr std::size_t kCentre = 4;
  std::vector<Vec2> trial = q;
  std::vector<SurfacePoint> trialSurface = p;
  for (int a = 1; a < kSteps; ++a)
    for (int b = keepDiagonal ? a : 1; keepDiagonal ? b == a : b < kSteps; ++b) {
      trial[kCentre] = Vec2{0.25 + 0.5 * a / kSteps, 0.25 + 0.5 * b / kSteps};
      if (!(convexChartQuad(trial, 3, 0, 0) && convexChartQuad(trial, 3, 1, 0) && convexChartQuad(trial, 3, 0, 1) &&
            convexChartQuad(trial, 3, 1, 1)))
        continue;
      trialSurface[kCentre] = surfaceAt(trial[kCentre]);
      const double error = levelError(3, trial, trialSurface, surfaceAt, vertices);
      if (error < best) best = error, q[kCentre] = trial[kCentre], p[kCentre] = trialSurface[kCentre];
    }
}

}  // namespace

bool convexChartQuad(const std::vector<Vec2>& q, std::uint32_t n, std::uint32_t i, std::uint32_t j) {
  const std::size_t k = std::size_t(j) * n + i;
  const std::array<Vec2, 4> c = {q[k], q[k + 1], q[k + n + 1], q[k + n]};
  for (int m = 0; m < 4; ++m)
    if (multires::exactOrientation(c[m], c[(m + 1) % 4], c[(m + 2) % 4]) <= 0) return false;
  return true;
}

unsigned convexAroundTexel(const std::vector<Vec2>& q, std::uint32_t n, std::uint32_t i, std::uint32_t j) {
  return unsigned(convexChartQuad(q, n, i - 1, j - 1)) | unsigned(convexChartQuad(q, n, i, j - 1)) << 1 |
         unsigned(convexChartQuad(q, n, i - 1, j)) << 2 | unsigned(convexChartQuad(q, n, i, j)) << 3;
}

std::vector<double> uniformFractions(std::uint32_t n) {
  std::vector<double> t(n);
  for (std::uint32_t m = 0; m < n; ++m) t[m] = double(m) / (n - 1);
  return t;
}

std::vector<double> relaxSide(std::uint32_t n, const std::function<SurfacePoint(double)>& surfaceAt, const ChartRelaxing& how) {
  std::vector<double> t = uniformFractions(n);
  const std::uint32_t stride = keptStride(n, how);
  if (how.sweeps <= 0 || stride <= 1) return t;
  // Equidistribution (de Boor) between the kept texels: place the texels at equal steps of the
  // weighted length measured through the last placement, a few times over as the samples move.
  constexpr int kRounds = 4;
  std::vector<SurfacePoint> p(n);
  std::vector<double> length(n);
  for (int round = 0; round < kRounds; ++round) {
    for (std::uint32_t m = 0; m < n; ++m) p[m] = surfaceAt(t[m]);
    length[0] = 0;
    for (std::uint32_t m = 1; m < n; ++m)
      length[m] = length[m - 1] + norm(p[m].position - p[m - 1].position) * spacingWeight(p[m - 1], p[m], how.flatCurvature);

    std::vector<double> next(n);
    next[0] = 0, next[n - 1] = 1;
    std::uint32_t seg = 0;
    for (std::uint32_t m = 1; m + 1 < n; ++m) {
      const std::uint32_t a = m / stride * stride, b = a + stride;
      if (m == a) {
        next[m] = t[m], seg = m;
        continue;
      }
      if (!(length[b] > length[a])) {  // no length to share out: keep the uniform steps
        next[m] = t[a] + (t[b] - t[a]) * (m - a) / stride;
        continue;
      }
      const double want = length[a] + (length[b] - length[a]) * (m - a) / stride;
      while (seg + 1 < b && length[seg + 1] < want) ++seg;
      const double span = length[seg + 1] - length[seg];
      next[m] = t[seg] + (t[seg + 1] - t[seg]) * (span > 0 ? std::clamp((want - length[seg]) / span, 0.0, 1.0) : 0);
    }
    // Fractions on a grid of 2^-32, so that 1 - t, the fraction from the side's other end (the chart
    // across reads it so), is exact; strictly increasing, the kept ones where they were.
    constexpr double kGrid = 4294967296.0;
    for (std::uint32_t m = 1; m + 1 < n; ++m) {
      const std::uint32_t b = m / stride * stride + stride;
      if (m % stride == 0) continue;
      next[m] = std::clamp(std::round(next[m] * kGrid) / kGrid, next[m - 1] + 1 / kGrid, next[b] - (b - m) / kGrid);
    }
    t = std::move(next);
  }
  return t;
}

std::vector<Vec2> refineChartGrid(std::uint32_t n, const std::vector<Vec2>& q, const std::array<std::vector<double>, 4>& sides,
                                  bool keepDiagonal) {
  const std::uint32_t f = 2 * n - 1;
  std::vector<Vec2> out(std::size_t(f) * f);
  auto at = [&](std::uint32_t i, std::uint32_t j) -> Vec2& { return out[std::size_t(j) * f + i]; };
  for (std::uint32_t j = 0; j < f; j += 2)
    for (std::uint32_t i = 0; i < f; ++i) {
      const Vec2 &a = q[std::size_t(j / 2) * n + i / 2], &b = q[std::size_t(j / 2) * n + (i + 1) / 2];
      at(i, j) = i % 2 ? (a + b) * 0.5 : a;
    }
  for (std::uint32_t j = 1; j < f; j += 2)
    for (std::uint32_t i = 0; i < f; i += 2) at(i, j) = (at(i, j - 1) + at(i, j + 1)) * 0.5;
  setBorder(f, sides, out);
  for (std::uint32_t j = 1; j < f; j += 2)
    for (std::uint32_t i = 1; i < f; i += 2)
      at(i, j) = keepDiagonal && i == j ? crossing(at(i - 1, j - 1), at(i + 1, j + 1), at(i, j - 1), at(i, j + 1))
                        : crossing(at(i - 1, j), at(i + 1, j), at(i, j - 1), at(i, j + 1));
  return out;
}

double coarsestRelaxedError(std::uint32_t n, int side, const std::vector<double>& fractions,
                            const std::function<SurfacePoint(const Vec2&)>& surfaceAt, const ChartRelaxing& how,
                            std::span<const ChartVertex> vertices) {
  const std::uint32_t stride = keptStride(n, how);
  if (how.sweeps <= 0 || stride < 2) return 0;
  const std::uint32_t size = (n - 1) / (stride / 2) + 1;
  std::array<std::vector<double>, 4> sides;
  for (int s = 0; s < 4; ++s) sides[std::size_t(s)] = s == side ? fractions : uniformFractions(n);
  const auto grids = sidesOfEveryGrid(sides);
  std::vector<Vec2> q = tileCorners();
  for (std::size_t l = grids.size() - 1; l-- > 0 && grids[l + 1][0].size() < size;) q = refineChartGrid(std::uint32_t(grids[l + 1][0].size()), q, grids[l], how.keepDiagonal);
  std::vector<SurfacePoint> p(q.size());
  for (std::size_t k = 0; k < q.size(); ++k) p[k] = surfaceAt(q[k]);
  return levelError(size, q, p, surfaceAt, vertices);
}

std::vector<Vec2> relaxChart(std::uint32_t n, const std::function<SurfacePoint(const Vec2&)>& surfaceAt,
                             const std::array<std::vector<double>, 4>& sides, const ChartRelaxing& how, std::uint32_t* nonConvex,
                             std::span<const ChartVertex> vertices) {
  // Coarse to fine, as the model's levels take the texels. The sides' fractions of every grid from
  // the tile's corners (2 a side) up to the chart's; the grids up to the kept one are only spanned by
  // their sides (their spacing is too coarse to see the bending), each finer one places its new
  // texels between the coarser ones, so that every level's texels are spread for that level.
  const std::uint32_t stride = keptStride(n, how);
  const auto grids = sidesOfEveryGrid(sides);
  std::vector<Vec2> q = tileCorners();
  std::vector<SurfacePoint> p;
  for (std::size_t l = grids.size() - 1; l-- > 0;) {
    const auto coarse = std::uint32_t(grids[l + 1][0].size()), fine = std::uint32_t(grids[l][0].size());
    q = refineChartGrid(coarse, q, grids[l], how.keepDiagonal);
    if (fine == 3 && how.sweeps > 0 && how.levelTwoGuard < std::numeric_limits<double>::infinity()) {
      p.resize(q.size());
      for (std::size_t k = 0; k < q.size(); ++k) p[k] = surfaceAt(q[k]);
      placeLevelTwoCentre(q, p, surfaceAt, vertices, how.levelTwoGuard, how.keepDiagonal);
    }
    const bool relaxed = how.sweeps > 0 && stride > 1 && (n - 1) / (fine - 1) < stride;
    if (!relaxed) {
      p.clear();
      continue;
    }
    std::vector<SurfacePoint> finer(q.size());
    for (std::uint32_t j = 0; j < fine; ++j)
      for (std::uint32_t i = 0; i < fine; ++i) {  // the coarser texels stay where they were measured
        const bool measured = !p.empty() && i % 2 == 0 && j % 2 == 0;
        finer[std::size_t(j) * fine + i] = measured ? p[std::size_t(j / 2) * coarse + i / 2] : surfaceAt(q[std::size_t(j) * fine + i]);
      }
    p = std::move(finer);
    // 5 and 9 a side take how.sweeps, each finer grid half as many, at least one.
    const int finerThanNine = std::max(0, int(std::log2(double(fine - 1))) - 3);
    const bool coarsestRelaxed = (n - 1) / (fine - 1) == stride / 2;
    const std::vector<Vec2> uniform = coarsestRelaxed ? q : std::vector<Vec2>{};
    const std::vector<SurfacePoint> uniformSurface = coarsestRelaxed ? p : std::vector<SurfacePoint>{};
    smoothNewTexels(fine, surfaceAt, how, std::max(1, how.sweeps >> finerThanNine), q, p);
    // The coarsest relaxed grid spans the tile with few texels, where the bending at them can pull
    // its triangles across a crease: it keeps its places only where its level lies no farther from
    // the surface, both ways.
    if (coarsestRelaxed && levelError(fine, q, p, surfaceAt, vertices) > levelError(fine, uniform, uniformSurface, surfaceAt, vertices))
      q = uniform, p = uniformSurface;
  }
  if (nonConvex) {
    *nonConvex = 0;
    for (std::uint32_t j = 0; j + 1 < n; ++j)
      for (std::uint32_t i = 0; i + 1 < n; ++i) *nonConvex += !convexChartQuad(q, n, i, j);
  }
  return q;
}

}  // namespace isoatlas::atlas
