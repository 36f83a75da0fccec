#include "atlas/make_atlas.h"

#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <limits>
#include <memory>

#include "atlas/hausdorff.h"
#include "atlas/tile_sides.h"
#include "core/error.h"
#include "core/progress.h"
#include "multires/dense_sampler.h"

namespace isoatlas::atlas {
namespace {

struct Sample {
  Vec3 position, normal;
};

// Texel (i, j) of every chart: the dense surface at the chart point. Marks the texels an image
// held (else the nearest image answered: a gap in the parametrisation) and counts the folded ones.
void sampleCharts(const Mesh& dense, const std::vector<Vec3>& normals, const multires::BaseMesh& base, Atlas& atlas,
                  std::vector<std::uint8_t>& held, ChartStats& stats) {
  const multires::DenseSampler sampler(dense, base);
  const std::uint32_t n = atlas.layout.chartSize;
  std::atomic<std::uint64_t> folded{0}, gaps{0};
  Progress progress("atlas: sampling charts", atlas.layout.charts, "charts");
  constexpr std::uint32_t kChunk = 256;  // charts between progress updates (Progress is not thread-safe)
  for (std::uint32_t first = 0; first < atlas.layout.charts; first += kChunk) {
  const std::uint32_t last = std::min(atlas.layout.charts, first + kChunk);
  tbb::parallel_for(first, last, [&](std::uint32_t c) {
    std::uint64_t foldedHere = 0, gapsHere = 0;
    for (std::uint32_t j = 0; j < n; ++j)
      for (std::uint32_t i = 0; i < n; ++i) {
        const auto [triangle, bary] = base.chartToTriangle(c, double(i) / (n - 1), double(j) / (n - 1));
        const multires::DenseSampler::Hit hit = sampler.locate(triangle, bary);
        foldedHere += hit.folded;
        gapsHere += !hit.held;
        Vec3 normal;
        if (hit.face == multires::DenseSampler::kNoFace) {
          const auto& t = base.triangles[triangle];
          normal = cross(base.positions[t[1]] - base.positions[t[0]], base.positions[t[2]] - base.positions[t[0]]);
        } else {
          const auto corners = dense.face(hit.face);
          for (int k = 0; k < 3; ++k) normal = normal + normals[corners[k]] * hit.bary[k];
        }
        const Vec3 p = sampler.hitPosition(triangle, hit);
        const std::size_t at = atlas.layout.texel(c, i, j);
        atlas.positions[at] = {float(p.x), float(p.y), float(p.z)};
        atlas.normals[at] = packNormal(normal);
        held[at] = hit.held;
      }
    folded += foldedHere;
    gaps += gapsHere;
  });
  progress.update(last);
  }
  progress.finish();
  stats.foldedTexels = folded;
  stats.gapTexels = gaps;
}

// Calls visit(k) for each 4-neighbour k of texel (i, j) of an n x n chart (texels row by row).
template <class Visit>
void forNeighbours(std::uint32_t n, std::uint32_t i, std::uint32_t j, Visit&& visit) {
  if (i > 0) visit(j * n + i - 1);
  if (i + 1 < n) visit(j * n + i + 1);
  if (j > 0) visit((j - 1) * n + i);
  if (j + 1 < n) visit((j + 1) * n + i);
}

// The odd texels of one chart's positions p (n x n, row by row): far from all their neighbours
// (more than kOutlier times the chart's median texel spacing) and from the neighbours' mean by
// more than kOutlier times their spread about it, so not a stretched but sound part of the chart.
// (Looser tests, counting texels with one close neighbour too, lowered bunny00's and fandisk's
// finest level: they caught sharp but sound places.)
std::vector<std::uint32_t> oddTexels(const std::vector<Vec3>& p, std::uint32_t n) {
  constexpr double kOutlier = 4;
  std::vector<double> spacing;
  for (std::uint32_t j = 0; j < n; ++j)
    for (std::uint32_t i = 0; i < n; ++i) {
      if (i + 1 < n) spacing.push_back(norm(p[j * n + i + 1] - p[j * n + i]));
      if (j + 1 < n) spacing.push_back(norm(p[(j + 1) * n + i] - p[j * n + i]));
    }
  std::nth_element(spacing.begin(), spacing.begin() + std::ptrdiff_t(spacing.size() / 2), spacing.end());
  const double limit = kOutlier * spacing[spacing.size() / 2];
  std::vector<std::uint32_t> odd;
  if (!(limit > 0)) return odd;
  for (std::uint32_t j = 0; j < n; ++j)
    for (std::uint32_t i = 0; i < n; ++i) {
      const Vec3& x = p[j * n + i];
      int close = 0, count = 0;
      Vec3 mean;
      forNeighbours(n, i, j, [&](std::uint32_t k) { close += !(norm(p[k] - x) > limit), mean = mean + p[k], ++count; });
      mean = mean * (1.0 / count);
      double spread = 0;
      forNeighbours(n, i, j, [&](std::uint32_t k) { spread = std::max(spread, norm(p[k] - mean)); });
      if (close == 0 && norm(x - mean) > kOutlier * spread) odd.push_back(j * n + i);
    }
  return odd;
}

}  // namespace

std::uint64_t repairOutliers(const Mesh& dense, const std::vector<Vec3>& normals, Atlas& atlas, std::vector<std::uint8_t>& held) {
  const std::uint32_t n = atlas.layout.chartSize;
  std::unique_ptr<NearestPoints> nearest;  // built on the first odd texel
  std::uint64_t repaired = 0;
  std::vector<Vec3> p(std::size_t(n) * n);
  for (std::uint32_t c = 0; c < atlas.layout.charts; ++c) {
    for (std::uint32_t j = 0; j < n; ++j)
      for (std::uint32_t i = 0; i < n; ++i) p[j * n + i] = atlas.position(c, i, j);
    const std::vector<std::uint32_t> odd = oddTexels(p, n);
    if (odd.empty()) continue;
    for (int sweep = 0; sweep < 64; ++sweep)  // Laplace's averaging over the odd texels
      for (const std::uint32_t t : odd) {
        Vec3 sum;
        int count = 0;
        forNeighbours(n, t % n, t / n, [&](std::uint32_t k) { sum = sum + p[k], ++count; });
        p[t] = sum * (1.0 / count);
      }
    if (!nearest) nearest = std::make_unique<NearestPoints>(dense);
    for (const std::uint32_t t : odd) {
      const NearestPoints::Hit hit = nearest->nearest(p[t]);
      Vec3 normal;
      const auto corners = dense.face(hit.face);
      for (int k = 0; k < 3; ++k) normal = normal + normals[corners[k]] * hit.bary[k];
      const std::size_t at = atlas.layout.texel(c, t % n, t / n);
      atlas.positions[at] = {float(hit.point.x), float(hit.point.y), float(hit.point.z)};
      atlas.normals[at] = packNormal(normal);
      held[at] = 1;
      ++repaired;
    }
  }
  return repaired;
}

namespace {

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

Atlas makeAtlas(const Mesh& dense, const multires::BaseMesh& base, std::uint32_t chartSize, ChartStats* stats) {
  require(multires::isChartSize(chartSize), "atlas: chart size " + std::to_string(chartSize) + " is not 2^k + 1 between 3 and " +
                                                std::to_string(multires::kMaxChartSize));
  require(!base.tiles.empty() && base.tiles.size() * 2 == base.triangleCount(),
          "atlas: the base mesh is not paired into tiles");
  const auto start = std::chrono::steady_clock::now();
  Atlas atlas;
  atlas.layout = packCharts(std::uint32_t(base.tiles.size()), chartSize);
  const std::size_t texels = std::size_t(atlas.layout.width()) * atlas.layout.height();
  atlas.positions.assign(texels, {0, 0, 0});
  atlas.normals.assign(texels, {0, 0, 0});
  ChartStats s;
  s.texels = std::uint64_t(atlas.layout.charts) * chartSize * chartSize;
  std::vector<std::uint8_t> held(texels, 0);
  const std::vector<Vec3> normals = vertexNormals(dense);
  sampleCharts(dense, normals, base, atlas, held, s);
  s.repairedTexels = repairOutliers(dense, normals, atlas, held);
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
