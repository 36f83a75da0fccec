#include "atlas/make_atlas.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>

#include "atlas/reconstruct.h"
#include "atlas/relax_chart.h"
#include "atlas/snap_texels.h"
#include "atlas/unturn_texels.h"
#include "atlas/tile_sides.h"
#include "core/error.h"
#include "core/progress.h"

namespace isoatlas::atlas {
namespace {

struct Sample {
  Vec3 position, normal;
};

// flatCurvature (relax_chart.h) as a share of the dense surface's median curvature: low enough
// that texels gather at creases, high enough that flat parts keep theirs.
constexpr double kFlatCurvatureShare = 0.1;

// The surface at chart point q of tile c, through the parametrisation's history, with its normal
// interpolated from the dense mesh's vertex normals.
struct ChartSurface {
  const Mesh& dense;
  const std::vector<Vec3>& normals;
  const multires::BaseMesh& base;
  multires::ParametrisationHistory::DensePoint point(std::uint32_t c, const multires::Vec2& q,
                                                     multires::ParametrisationHistory::Hints* hints = nullptr) const {
    const auto [triangle, bary] = base.chartToTriangle(c, q.x, q.y);
    return base.densePoint(triangle, bary, hints);
  }
  Vec3 faceNormal(const multires::ParametrisationHistory::DensePoint& point) const {
    const auto c = dense.face(point.face);
    return cross(dense.positions[c[1]] - dense.positions[c[0]], dense.positions[c[2]] - dense.positions[c[0]]);
  }
  Vec3 normal(const multires::ParametrisationHistory::DensePoint& point) const {
    Vec3 normal;
    const auto corners = dense.face(point.face);
    for (int k = 0; k < 3; ++k) normal = normal + normals[corners[k]] * point.bary[k];
    return normal;
  }
  SurfacePoint at(const multires::ParametrisationHistory::DensePoint& p) const {
    const Vec3 n = normal(p);
    const double length = norm(n);
    return {multires::densePosition(dense, p), length > 0 ? n * (1 / length) : n};
  }
};

// The surface at the points of one chart, each point carried back through the history once:
// relaxing, placing and snapping the texels ask again for many of the same points (the same bits).
// The way back of one point hints the next's (ParametrisationHistory::Hints). One cache serves a
// thread from chart to chart (ChartPointCaches), so that starting a chart (`on`) neither allocates
// nor clears a table: a generation per chart says which slots are in use.
class ChartPointCache {
public:
  explicit ChartPointCache(const ChartSurface& surface) : surface_(surface), slots_(kFirstSlots) {}
  // Forgets the points of the chart before (unless it is the same one) and serves chart c.
  ChartPointCache& on(std::uint32_t chart) {
    if (chart == chart_) return *this;
    chart_ = chart;
    points_.clear();
    if (++generation_ == 0) {  // wrapped: the slots' generations start again
      std::fill(slots_.begin(), slots_.end(), Slot{});
      generation_ = 1;
    }
    return *this;
  }
  multires::ParametrisationHistory::DensePoint point(const multires::Vec2& q) {
    const Key key{std::bit_cast<std::uint64_t>(q.x), std::bit_cast<std::uint64_t>(q.y)};
    Slot& slot = slotOf(key);
    if (slot.generation == generation_) return points_[slot.point];
    const multires::ParametrisationHistory::DensePoint p = surface_.point(chart_, q, &hints_);
    slot = {key, generation_, std::uint32_t(points_.size())};
    points_.push_back(p);
    if (points_.size() * 2 > slots_.size()) grow();
    return p;
  }
  SurfacePoint at(const multires::Vec2& q) { return surface_.at(point(q)); }
  Vec3 position(const multires::Vec2& q) { return multires::densePosition(surface_.dense, point(q)); }

private:
  // A table of its own (open addressing, linear probing, at most half full): a node-based map's
  // allocations cost about what the walks it saved.
  static constexpr std::size_t kFirstSlots = 4096;
  static constexpr std::uint32_t kNoChart = ~0u;
  using Key = std::array<std::uint64_t, 2>;
  struct Slot {
    Key key{};
    std::uint32_t generation = 0, point = 0;  // point: its place in points_
  };
  Slot& slotOf(const Key& key) {
    const std::size_t mask = slots_.size() - 1;
    std::size_t at = std::size_t((key[0] * 0x9E3779B97F4A7C15ull ^ key[1]) * 0xC2B2AE3D27D4EB4Full >> 20) & mask;
    while (slots_[at].generation == generation_ && slots_[at].key != key) at = (at + 1) & mask;
    return slots_[at];
  }
  void grow() {
    std::vector<Slot> old(2 * slots_.size());
    old.swap(slots_);
    for (const Slot& slot : old)
      if (slot.generation == generation_) slotOf(slot.key) = slot;
  }
  const ChartSurface& surface_;
  std::uint32_t chart_ = kNoChart, generation_ = 1;
  std::vector<Slot> slots_;
  std::vector<multires::ParametrisationHistory::DensePoint> points_;
  multires::ParametrisationHistory::Hints hints_;
};

// A ChartPointCache per thread. A chart's work must not run parallel algorithms of its own: the
// thread could take up another chart midway, and its cache with it.
struct ChartPointCaches {
  explicit ChartPointCaches(const ChartSurface& surface) : caches(surface) {}
  ChartPointCache& on(std::uint32_t chart) { return caches.local().on(chart); }
  tbb::enumerable_thread_specific<ChartPointCache> caches;
};

// A typical bending of the dense surface: the median over its edges of |n_a - n_b| / |p_a - p_b|.
double medianEdgeCurvature(const Mesh& dense, const std::vector<Vec3>& normals) {
  std::vector<double> curvatures;
  curvatures.reserve(dense.faceVertices.size());
  for (std::size_t f = 0; f < dense.faceCount(); ++f) {
    const auto c = dense.face(f);
    for (std::size_t k = 0; k < c.size(); ++k) {
      const std::uint32_t a = c[k], b = c[(k + 1) % c.size()];
      const double length = norm(dense.positions[b] - dense.positions[a]);
      const double na = norm(normals[a]), nb = norm(normals[b]);
      if (length > 0 && na > 0 && nb > 0) curvatures.push_back(norm(normals[b] * (1 / nb) - normals[a] * (1 / na)) / length);
    }
  }
  if (curvatures.empty()) return 1;
  std::nth_element(curvatures.begin(), curvatures.begin() + curvatures.size() / 2, curvatures.end());
  return curvatures[curvatures.size() / 2];
}

// Per chart and side, the fractions along the side where its texels sit: computed once per base
// edge, from its lower chart, and given reversed to the chart across. relaxSide's, or, where the
// coarsest relaxed grid (coarsestRelaxedError) would lie farther from the surface so on either chart
// than with its texels uniform, relaxSide's with those texels kept (a kept grid twice as fine).
std::vector<std::array<std::vector<double>, 4>> sideFractions(const ChartSurface& surface, const AtlasLayout& layout,
                                                              const ChartRelaxing& how,
                                                              const std::vector<std::vector<ChartVertex>>& chartVertices) {
  const std::uint32_t n = layout.chartSize;
  const auto across = sidesAcross(surface.base);
  auto verticesOf = [&](std::uint32_t c) { return chartVertices.empty() ? std::span<const ChartVertex>{} : std::span(chartVertices[c]); };
  const std::vector<double> uniform = uniformFractions(n);
  auto reversed = [&](const std::vector<double>& t) {
    std::vector<double> back(n);
    for (std::uint32_t m = 0; m < n; ++m) back[m] = 1 - t[n - 1 - m];
    back.front() = 0, back.back() = 1;
    return back;
  };
  ChartRelaxing coarser = how;
  coarser.keptSize = 2 * how.keptSize - 1;
  const bool guarded = how.sweeps > 0 && coarser.keptSize < n;
  std::vector<double> uniformError(guarded ? layout.charts : 0);  // per chart, with every side uniform
  ChartPointCaches caches(surface), acrossCaches(surface);
  tbb::parallel_for(std::uint32_t(0), std::uint32_t(uniformError.size()), [&](std::uint32_t c) {
    ChartPointCache& cache = caches.on(c);
    uniformError[c] = coarsestRelaxedError(n, 0, uniform, [&](const multires::Vec2& q) { return cache.at(q); }, how, verticesOf(c));
  });
  std::vector<std::array<std::vector<double>, 4>> sides(layout.charts);
  tbb::parallel_for(std::uint32_t(0), layout.charts, [&](std::uint32_t c) {
    ChartPointCache& cache = caches.on(c);
    for (int s = 0; s < 4; ++s) {
      const SideAcross other = across[c][s];
      if (other.tile != kNoTile && other.tile < c) continue;
      auto alongSide = [&](double f) { return cache.at(sidePoint(s, f)); };
      std::vector<double> t = relaxSide(n, alongSide, how);
      if (guarded) {
        double error = coarsestRelaxedError(n, s, t, [&](const multires::Vec2& q) { return cache.at(q); }, how, verticesOf(c));
        double uniformTexels = uniformError[c];
        if (other.tile != kNoTile) {
          ChartPointCache& acrossCache = acrossCaches.on(other.tile);
          error = std::max(error, coarsestRelaxedError(n, other.side, reversed(t), [&](const multires::Vec2& q) { return acrossCache.at(q); },
                                                       how, verticesOf(other.tile)));
          uniformTexels = std::max(uniformTexels, uniformError[other.tile]);
        }
        if (error > uniformTexels) t = relaxSide(n, alongSide, coarser);
      }
      if (other.tile != kNoTile) sides[other.tile][other.side] = reversed(t);
      sides[c][s] = t;
    }
  });
  return sides;
}

// Per tile, the dense vertices strictly inside its chart, at their places on the base mesh (the
// simplification's forward map); empty when the base mesh has none.
std::vector<std::vector<ChartVertex>> verticesInCharts(const Mesh& dense, const multires::BaseMesh& base) {
  if (base.denseTriangle.size() != dense.vertexCount()) return {};
  std::vector<std::uint32_t> tileOf(base.triangleCount());
  for (std::uint32_t t = 0; t < base.tiles.size(); ++t) tileOf[base.tiles[t][0]] = tileOf[base.tiles[t][1]] = t;
  std::vector<std::vector<ChartVertex>> out(base.tiles.size());
  for (std::uint32_t d = 0; d < dense.vertexCount(); ++d) {
    const std::uint32_t triangle = base.denseTriangle[d], tile = tileOf[triangle];
    const auto [u, v] = base.triangleToChart(tile, triangle, base.denseBary[d]);
    if (u > 0 && u < 1 && v > 0 && v < 1) out[tile].push_back({{u, v}, dense.positions[d]});
  }
  return out;
}

// ChartRelaxing::levelTwoGuard as a share of level 0's largest distance over the tiles (levelError,
// which measures at chart points and so overstates the closest distance: the white matter's level 0
// measures 0.85 of it by CGAL's Hausdorff distance). A tile's level 2 below it lies well within
// level 0's largest distance, and its centre stays: the finer levels are relaxed around it.
constexpr double kLevelTwoGuardShare = 0.8;

// Level 0's largest distance from the surface over the tiles: each tile's two base triangles against
// the surface and its dense vertices (levelError of the grid of 2).
double largestLevelZeroError(const ChartSurface& surface, std::uint32_t charts,
                             const std::vector<std::vector<ChartVertex>>& chartVertices) {
  std::vector<double> error(charts);
  ChartPointCaches caches(surface);
  tbb::parallel_for(std::uint32_t(0), charts, [&](std::uint32_t c) {
    ChartPointCache& cache = caches.on(c);
    error[c] = levelZeroError([&](const multires::Vec2& q) { return cache.at(q); }, chartVertices[c]);
  });
  return error.empty() ? 0 : *std::max_element(error.begin(), error.end());
}

// The chart points of tile c (relaxChart), then its finest texels drawn onto the dense vertices the
// grid misses (snapTexels) and moved where fewer triangles round them face backwards (unturnTexels;
// both with relaxation only, so that no relaxation keeps the tile's uniform grid), and the dense
// surface at each.
struct ChartPoints {
  std::vector<multires::Vec2> chart;
  std::vector<multires::ParametrisationHistory::DensePoint> dense;
  std::uint32_t nonConvex = 0, snapped = 0, unturned = 0;
  bool levelTwoCentreMoved = false;  // by ChartRelaxing::levelTwoGuard
  bool keptDiagonal = false;         // ChartRelaxing::keepDiagonal
};
// Whether the tile's diagonal, where its two base triangles meet, is a crease of the dense mesh:
// every one of kSamples points strictly along it lands on an edge of a dense face (a weight of 0, to
// rounding), as where the base mesh keeps the dense mesh's edges (a polyhedron's base can be
// itself), and at one of them at least the faces just either side turn by more than kCreaseDegrees.
// Along a smooth run of dense edges (bunny00 has 9 such tiles of 752) the texels stay free.
bool diagonalIsADenseCrease(const ChartSurface& surface, ChartPointCache& cache) {
  constexpr int kSamples = 15;
  constexpr double kCreaseDegrees = 2, kBeside = 1e-6;
  bool crease = false;
  for (int k = 1; k <= kSamples; ++k) {
    const double t = double(k) / (kSamples + 1);
    const auto& bary = cache.point({t, t}).bary;
    if (std::min({bary[0], bary[1], bary[2]}) > 1e-9) return false;
    const Vec3 a = surface.faceNormal(cache.point({t + kBeside, t - kBeside})), b = surface.faceNormal(cache.point({t - kBeside, t + kBeside}));
    crease |= dot(a, b) < std::cos(kCreaseDegrees * M_PI / 180) * norm(a) * norm(b);
  }
  return crease;
}

ChartPoints placeTexels(const ChartSurface& surface, ChartPointCache& cache, std::uint32_t n, const std::array<std::vector<double>, 4>& sides,
                        ChartRelaxing how, std::span<const ChartVertex> vertices) {
  ChartPoints out;
  how.keepDiagonal = how.sweeps > 0 && diagonalIsADenseCrease(surface, cache);
  out.keptDiagonal = how.keepDiagonal;
  out.chart = relaxChart(n, [&](const multires::Vec2& q) { return cache.at(q); }, sides, how, &out.nonConvex, vertices);
  out.levelTwoCentreMoved = levelTwoCentreMoved(n, out.chart);
  out.dense.resize(out.chart.size());
  for (std::size_t k = 0; k < out.chart.size(); ++k) out.dense[k] = cache.point(out.chart[k]);
  if (how.sweeps <= 0 || vertices.empty()) return out;
  std::vector<Vec3> positions(out.chart.size());
  for (std::size_t k = 0; k < positions.size(); ++k) positions[k] = multires::densePosition(surface.dense, out.dense[k]);
  const std::vector<multires::Vec2> before = out.chart;
  out.snapped = snapTexels(n, vertices, [&](const multires::Vec2& q) { return cache.position(q); }, out.chart, positions, how.keepDiagonal);
  // With the dense faces' own normals: what unturnTexels lowers is the fold measure (backfacing_quads.h).
  auto facing = [&](const multires::Vec2& q) {
    const multires::ParametrisationHistory::DensePoint point = cache.point(q);
    const Vec3 n = surface.faceNormal(point);
    const double length = norm(n);
    return SurfacePoint{multires::densePosition(surface.dense, point), length > 0 ? n * (1 / length) : n};
  };
  out.unturned = unturnTexels(n, vertices, facing, out.chart, positions, how.keepDiagonal);
  for (std::size_t k = 0; k < out.chart.size(); ++k)
    if (out.chart[k].x != before[k].x || out.chart[k].y != before[k].y) out.dense[k] = cache.point(out.chart[k]);
  return out;
}

// Atlas::triangleFaceNormals of chart c, its chart points q: the dense face under each finest
// triangle's centroid in the chart.
void writeTriangleFaceNormals(const ChartSurface& surface, ChartPointCache& cache, std::uint32_t c, const std::vector<multires::Vec2>& q,
                              Atlas& atlas) {
  const std::uint32_t n = atlas.layout.chartSize;
  for (std::uint32_t b = 0; b + 1 < n; ++b)
    for (std::uint32_t a = 0; a + 1 < n; ++a) {
      const std::array<std::size_t, 4> corner{b * n + a, b * n + a + 1, (b + 1) * n + a + 1, (b + 1) * n + a};
      const auto triangles = squareTriangles(a, b);
      for (int t = 0; t < 2; ++t) {
        multires::Vec2 centroid;
        for (const int k : triangles[std::size_t(t)]) centroid = centroid + q[corner[std::size_t(k)]];
        const Vec3 normal = surface.faceNormal(cache.point(centroid * (1.0 / 3)));
        // A face of no area faces no way: left zero, it judges no triangle folded.
        if (norm(normal) > 0) atlas.triangleFaceNormals[2 * atlas.layout.texel(c, a, b) + std::size_t(t)] = packNormal(normal);
      }
    }
}

// Texel (i, j) of every chart: the dense surface at its chart point (relaxChart), through the
// parametrisation's history (one-to-one and onto by construction). Counts the texels that some step
// of the way back found outside its ring by more than rounding (gaps: sent to the nearest face), and
// the texels that land where another texel of their chart does (folds: one place of the surface
// claimed twice), and the texel quads whose corners, taken in chart order, turn against the
// surface's normal (where the map shears hard, neighbouring texels land out of order even though
// the map is one-to-one).
void sampleCharts(const ChartSurface& surface, const ChartRelaxing& how, const std::vector<std::vector<ChartVertex>>& chartVertices,
                  Atlas& atlas, std::vector<std::uint8_t>& held, ChartStats& stats) {
  const std::uint32_t n = atlas.layout.chartSize;
  const auto sides = sideFractions(surface, atlas.layout, how, chartVertices);
  std::atomic<std::uint64_t> folded{0}, gaps{0}, steps{0}, turned{0}, nonConvex{0}, snapped{0}, unturned{0}, centresMoved{0}, keptDiagonals{0};
  Progress progress("atlas: sampling charts", atlas.layout.charts, "charts");
  constexpr std::uint32_t kChunk = 64;  // charts between progress updates (Progress is not thread-safe)
  ChartPointCaches caches(surface);
  for (std::uint32_t first = 0; first < atlas.layout.charts; first += kChunk) {
  const std::uint32_t last = std::min(atlas.layout.charts, first + kChunk);
  tbb::parallel_for(first, last, [&](std::uint32_t c) {
    std::uint64_t gapsHere = 0, stepsHere = 0;
    ChartPointCache& cache = caches.on(c);
    const ChartPoints points =
        placeTexels(surface, cache, n, sides[c], how, chartVertices.empty() ? std::span<const ChartVertex>{} : chartVertices[c]);
    writeTriangleFaceNormals(surface, cache, c, points.chart, atlas);
    snapped += points.snapped;
    unturned += points.unturned;
    centresMoved += points.levelTwoCentreMoved;
    keptDiagonals += points.keptDiagonal;
    std::vector<std::array<float, 3>> chart;
    std::vector<Vec3> positions, surfaceNormals;
    for (std::uint32_t j = 0; j < n; ++j)
      for (std::uint32_t i = 0; i < n; ++i) {
        const multires::ParametrisationHistory::DensePoint& point = points.dense[j * n + i];
        const bool gap = point.outside > multires::ParametrisationHistory::kGapWeight;
        gapsHere += gap;
        stepsHere += point.steps;
        const Vec3 normal = surface.normal(point);
        const Vec3 p = multires::densePosition(surface.dense, point);
        const std::size_t at = atlas.layout.texel(c, i, j);
        atlas.positions[at] = {float(p.x), float(p.y), float(p.z)};
        atlas.normals[at] = packNormal(normal);
        held[at] = !gap;
        chart.push_back(atlas.positions[at]);
        positions.push_back(p);
        surfaceNormals.push_back(normal);
      }
    std::uint64_t turnedHere = 0;
    for (std::uint32_t j = 0; j + 1 < n; ++j)
      for (std::uint32_t i = 0; i + 1 < n; ++i) {
        const std::size_t k = j * n + i;
        const Vec3 across = cross(positions[k + 1] - positions[k], positions[k + n] - positions[k]);
        turnedHere += dot(across, surfaceNormals[k]) < 0;
      }
    turned += turnedHere;
    std::sort(chart.begin(), chart.end());
    std::uint64_t foldedHere = 0;
    for (std::size_t k = 1; k < chart.size(); ++k) foldedHere += chart[k] == chart[k - 1];
    folded += foldedHere;
    gaps += gapsHere;
    steps += stepsHere;
    nonConvex += points.nonConvex;
  });
  progress.update(last);
  }
  progress.finish();
  stats.coincidentTexels = folded;
  stats.snappedTexels = snapped;
  stats.unturnedTexels = unturned;
  stats.levelTwoCentresMoved = centresMoved;
  stats.keptDiagonals = keptDiagonals;
  stats.gapTexels = gaps;
  stats.turnedTexelQuads = turned;
  stats.nonConvexChartQuads = nonConvex;
  stats.meanHistorySteps = double(steps) / double(std::max<std::uint64_t>(1, stats.texels));
}


// Every base edge's samples averaged over the charts whose sides run along it, and every corner set
// to its base vertex, the same floats written into each chart. Only samples an image held take
// part when some did (a sample from a gap may lie far off); and where those disagree by more than
// `tolerance` they found different sheets of a fold, whose mean would lie off the surface, so the
// first chart's sample is taken. Counts the shared sides and the disagreeing samples.
void averageSharedBorders(const multires::BaseMesh& base, const std::vector<std::uint8_t>& held, double tolerance,
                          Atlas& atlas, ChartStats& stats) {
  const std::uint32_t n = atlas.layout.chartSize;
  auto positionAt = [&](std::size_t at) { return Vec3{atlas.positions[at][0], atlas.positions[at][1], atlas.positions[at][2]}; };
  const auto across = sidesAcross(base);
  for (std::uint32_t c = 0; c < atlas.layout.charts; ++c)
    for (int s = 0; s < 4; ++s) {
      const SideAcross other = across[c][s];
      if (other.tile == kNoTile || other.tile < c) continue;  // each shared edge once, from its lower chart
      stats.sharedSides += 2;
      for (std::uint32_t m = 1; m + 1 < n; ++m) {
        const auto ij = sideTexel(s, m, n), kl = sideTexel(other.side, n - 1 - m, n);
        const std::size_t both[2] = {atlas.layout.texel(c, ij[0], ij[1]), atlas.layout.texel(other.tile, kl[0], kl[1])};
        std::vector<std::size_t> takes;
        for (const std::size_t at : both)
          if (held[at] || !(held[both[0]] || held[both[1]])) takes.push_back(at);
        if (takes.size() == 2 && norm(positionAt(takes[1]) - positionAt(takes[0])) > tolerance) {
          ++stats.borderDisagreements;
          takes.resize(1);
        }
        Sample sum{};
        for (const std::size_t at : takes) {
          sum.position = sum.position + positionAt(at);
          sum.normal = sum.normal + unpackNormal(atlas.normals[at]);
        }
        const Vec3 p = sum.position * (1.0 / double(takes.size()));
        const std::array<float, 3> position{float(p.x), float(p.y), float(p.z)};
        const Normal16 normal = packNormal(sum.normal);
        for (const std::size_t at : both) atlas.positions[at] = position, atlas.normals[at] = normal;
      }
    }
  // Corners: the base vertex's position, and the mean of the corner normals around it.
  std::vector<Vec3> cornerNormals(base.vertexCount());
  auto forCorners = [&](auto&& visit) {
    for (std::uint32_t c = 0; c < atlas.layout.charts; ++c) {
      const auto sides = tileSides(base, c);
      for (int s = 0; s < 4; ++s) {
        const auto ij = sideTexel(s, 0, n);
        visit(sides[s].from, atlas.layout.texel(c, ij[0], ij[1]));
      }
    }
  };
  forCorners([&](std::uint32_t v, std::size_t at) { cornerNormals[v] = cornerNormals[v] + unpackNormal(atlas.normals[at]); });
  forCorners([&](std::uint32_t v, std::size_t at) {
    const Vec3& p = base.positions[v];
    atlas.positions[at] = {float(p.x), float(p.y), float(p.z)};
    atlas.normals[at] = packNormal(cornerNormals[v]);
  });
}

}  // namespace

Atlas makeAtlas(const Mesh& dense, const multires::BaseMesh& base, std::uint32_t chartSize, ChartStats* stats, int relaxSweeps) {
  require(multires::isChartSize(chartSize), "atlas: chart size " + std::to_string(chartSize) + " is not 2^k + 1 between 3 and " +
                                                std::to_string(multires::kMaxChartSize));
  require(!base.tiles.empty() && base.tiles.size() * 2 == base.triangleCount(),
          "atlas: the base mesh is not paired into tiles");
  require(base.history && base.historyFrames.size() == base.triangleCount(),
          "atlas: the base mesh has no parametrisation (build the model from the dense mesh again)");
  const auto start = std::chrono::steady_clock::now();
  Atlas atlas;
  atlas.layout = packCharts(std::uint32_t(base.tiles.size()), chartSize);
  const std::size_t texels = std::size_t(atlas.layout.width()) * atlas.layout.height();
  atlas.positions.assign(texels, {0, 0, 0});
  atlas.normals.assign(texels, {0, 0, 0});
  atlas.triangleFaceNormals.assign(2 * texels, {0, 0, 0});
  ChartStats s;
  s.texels = std::uint64_t(atlas.layout.charts) * chartSize * chartSize;
  std::vector<std::uint8_t> held(texels, 0);
  const std::vector<Vec3> normals = vertexNormals(dense);
  // Floored at a tenth of a sphere the size of the mesh, for meshes mostly flat (a box's median is 0).
  const double flat = std::max(kFlatCurvatureShare * medianEdgeCurvature(dense, normals), 0.1 / boundingBox(dense.positions).diagonal());
  ChartRelaxing how{relaxSweeps, flat};
  const auto chartVertices = verticesInCharts(dense, base);
  const ChartSurface surface{dense, normals, base};
  if (relaxSweeps > 0 && !chartVertices.empty())
    how.levelTwoGuard = kLevelTwoGuardShare * largestLevelZeroError(surface, atlas.layout.charts, chartVertices);
  sampleCharts(surface, how, chartVertices, atlas, held, s);
  // Samples of one point may differ by float rounding (a few ulps of the coordinates), no more.
  const Box box = boundingBox(base.positions);
  const double largest = std::max({std::abs(box.min.x), std::abs(box.min.y), std::abs(box.min.z), std::abs(box.max.x),
                                   std::abs(box.max.y), std::abs(box.max.z)});
  const double tolerance = std::max(1e-6 * box.diagonal(), 8 * double(std::numeric_limits<float>::epsilon()) * largest);
  averageSharedBorders(base, held, tolerance, atlas, s);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (stats) *stats = s;
  return atlas;
}

}  // namespace isoatlas::atlas
