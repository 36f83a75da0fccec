#include "multires/untangle_parametrisation.h"

#include <algorithm>
#include <chrono>
#include <limits>

#include "core/error.h"
#include "multires/base_domain.h"

namespace isoatlas::multires {
namespace {

// Twice the signed area of a dense triangle's image in one chart that holds its corners (a base
// triangle's own frame has area 1 in these units; the other frames that hold the image are affine
// images of it, so the sign holds there too); -inf when its corners share no chart.
double imageArea(const Mesh& dense, const BaseDomain& domain, std::size_t face, BaseDomain::Chart& chart) {
  std::array<BaseDomain::Point2, 3> p;
  if (!domain.chartDenseTriangle(dense.face(face), chart, p)) return -std::numeric_limits<double>::infinity();
  return orient2(p[0], p[1], p[2]);
}

constexpr double kFlat = 1e-14;

std::vector<std::uint32_t> foldedTriangles(const Mesh& dense, const BaseDomain& domain) {
  BaseDomain::Chart chart;
  std::vector<std::uint32_t> folded;
  for (std::size_t f = 0; f < dense.faceCount(); ++f)
    if (imageArea(dense, domain, f, chart) <= kFlat) folded.push_back(std::uint32_t(f));
  return folded;
}

}  // namespace

std::size_t countFoldedTriangles(const Mesh& dense, const BaseMesh& base) {
  return foldedTriangles(dense, BaseDomain(base)).size();
}

UntangleStats untangleParametrisation(const Mesh& dense, BaseMesh& base) {
  const auto start = std::chrono::steady_clock::now();
  require(base.denseTriangle.size() == dense.vertexCount(), "untangle: the parametrisation does not match the mesh");
  require(dense.allFacesHave(3), "untangle: the dense mesh must be made of triangles");
  const BaseDomain domain(base);
  const VertexAdjacency adjacency = vertexAdjacency(dense);
  const Rows& neighbours = adjacency.neighbours;
  const Rows& faces = adjacency.faces;
  std::vector<char> fixed = adjacency.boundary;
  for (const std::int64_t d : base.denseVertex)
    if (d >= 0) fixed[std::size_t(d)] = 1;

  UntangleStats stats;
  BaseDomain::Chart chart;
  std::vector<std::uint32_t> folded = foldedTriangles(dense, domain);
  stats.foldedBefore = folded.size();

  // A new place for v: inside the kernel of its link (where every face around it turns
  // counter-clockwise) when that is not empty, at the kernel's centre; else the average of its
  // neighbours (Tutte's step). All in one chart that holds v's neighbours.
  std::vector<std::uint32_t> from;
  std::vector<BaseDomain::Bary> fromBary;
  std::vector<BaseDomain::Point2> kernel, clipped;
  BaseDomain::Chart relaxChart;
  auto place = [&](std::uint32_t v) {
    const std::uint32_t home = base.denseTriangle[v];
    from.clear();
    fromBary.clear();
    for (const std::uint32_t w : neighbours.of(v)) from.push_back(base.denseTriangle[w]), fromBary.push_back(base.denseBary[w]);
    if (from.empty() || !domain.chartFor(from.data(), fromBary.data(), from.size(), home, relaxChart)) return false;
    auto at = [&](std::uint32_t w, BaseDomain::Point2& p) {
      return domain.toChart(relaxChart, base.denseTriangle[w], base.denseBary[w], p);
    };
    BaseDomain::Point2 sum, p, lo{1e300, 1e300}, hi{-1e300, -1e300};
    for (const std::uint32_t w : neighbours.of(v)) {
      if (!at(w, p)) return false;
      sum.x += p.x, sum.y += p.y;
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)}, hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
    }
    kernel = {lo, {hi.x, lo.y}, hi, {lo.x, hi.y}};
    for (const std::uint32_t f : faces.of(v)) {
      const auto c = dense.face(f);
      const std::size_t i = std::size_t(std::find(c.begin(), c.end(), v) - c.begin());
      BaseDomain::Point2 a, b;
      if (!at(c[(i + 1) % 3], a) || !at(c[(i + 2) % 3], b)) return false;
      // Keep the side where (a, b, p) turns counter-clockwise.
      auto side = [&](const BaseDomain::Point2& q) { return orient2(a, b, q); };
      clipped.clear();
      for (std::size_t k = 0; k < kernel.size(); ++k) {
        const BaseDomain::Point2& q0 = kernel[k];
        const BaseDomain::Point2& q1 = kernel[(k + 1) % kernel.size()];
        const double s0 = side(q0), s1 = side(q1);
        if (s0 >= 0) clipped.push_back(q0);
        if ((s0 >= 0) != (s1 >= 0)) {
          const double t = s0 / (s0 - s1);
          clipped.push_back({q0.x + t * (q1.x - q0.x), q0.y + t * (q1.y - q0.y)});
        }
      }
      kernel.swap(clipped);
      if (kernel.empty()) break;
    }
    const double count = double(from.size());
    BaseDomain::Point2 target{sum.x / count, sum.y / count};
    if (kernel.size() >= 3) {
      BaseDomain::Point2 centre;
      for (const BaseDomain::Point2& q : kernel) centre.x += q.x, centre.y += q.y;
      target = {centre.x / double(kernel.size()), centre.y / double(kernel.size())};
    }
    domain.fromChart(relaxChart, target, base.denseTriangle[v], base.denseBary[v]);
    return true;
  };
  // How folded v's faces are: their count, then the most negative area.
  auto foldsAround = [&](std::uint32_t v) {
    std::pair<int, double> score{0, 0};
    for (const std::uint32_t f : faces.of(v)) {
      const double area = imageArea(dense, domain, f, chart);
      if (area <= kFlat) ++score.first, score.second = std::max(score.second, kFlat - area);
    }
    return score;
  };

  // Greedy: a vertex of a folded face moves (place) when that leaves fewer folds around it, or as
  // many but shallower; only its own faces change, so the count never grows. Each pass starts from
  // the faces still folded; when a pass moves nothing, the folds' neighbours become candidates too.
  std::vector<char> relaxed(dense.vertexCount(), 0), queued(dense.vertexCount(), 0);
  std::vector<std::uint32_t> candidates;
  constexpr int kPasses = 30;
  for (int pass = 0; pass < kPasses && !folded.empty(); ++pass) {
    candidates.clear();
    for (const std::uint32_t f : folded)
      for (const std::uint32_t v : dense.face(f)) {
        if (!fixed[v] && !queued[v]) queued[v] = 1, candidates.push_back(v);
        for (const std::uint32_t w : neighbours.of(v))  // the ring too: a fold can need room
          if (pass >= kPasses / 2 && !fixed[w] && !queued[w]) queued[w] = 1, candidates.push_back(w);
      }
    bool changed = false;
    for (const std::uint32_t v : candidates) {
      queued[v] = 0;
      const auto before = foldsAround(v);
      const std::uint32_t t = base.denseTriangle[v];
      const BaseDomain::Bary b = base.denseBary[v];
      if (!place(v)) continue;
      const auto after = foldsAround(v);
      if (after.first < before.first || (after.first == before.first && after.second < before.second)) {
        relaxed[v] = 1, changed = true;
      } else {
        base.denseTriangle[v] = t, base.denseBary[v] = b;
      }
    }
    // Still folded: the faces around the moved candidates, and the folded ones none could move.
    std::vector<std::uint32_t> recheck;
    recheck.swap(folded);
    for (const std::uint32_t v : candidates)
      for (const std::uint32_t f : faces.of(v)) recheck.push_back(f);
    std::sort(recheck.begin(), recheck.end());
    recheck.erase(std::unique(recheck.begin(), recheck.end()), recheck.end());
    for (const std::uint32_t f : recheck)
      if (imageArea(dense, domain, f, chart) <= kFlat) folded.push_back(f);
    if (!changed && pass < kPasses / 2) pass = kPasses / 2 - 1;  // stuck: widen to the rings
    else if (!changed) break;
  }
  stats.foldedAfter = folded.size();
  for (const char m : relaxed) stats.movedVertices += m;
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace isoatlas::multires
