#include "multires/weld_ranking.h"

#include <algorithm>
#include <limits>

#include "multires/exponential_map.h"
#include "multires/weld_plan.h"

namespace isoatlas::multires::simplify {

void initQuadrics(const StellarMesh& mesh, HugePageVector<Quadric>& quadric) {
  quadric.assign(mesh.n_vertices(), {});
  for (const FaceH f : mesh.faces()) {
    Vec3 p[3];
    int i = 0;
    for (const VertexH v : mesh.fv_range(f)) p[i++] = pointOf(mesh, v);
    const Vec3 n = cross(p[1] - p[0], p[2] - p[0]);
    const double twiceArea = norm(n);
    if (!(twiceArea > 0)) continue;
    const Vec3 unit = n * (1 / twiceArea);
    const Quadric q = Quadric::plane(unit, -dot(unit, p[0]), twiceArea / 6);  // a third of the area each
    for (const VertexH v : mesh.fv_range(f)) quadric[v.idx()] += q;
  }
  // Boundary edges: a plane through the edge, perpendicular to its face, weighted strongly so welds
  // along the boundary keep its course.
  constexpr double kBoundaryWeight = 10;
  for (const HalfedgeH h : mesh.halfedges()) {
    if (!mesh.is_boundary(h)) continue;
    const HalfedgeH inner = mesh.opposite_halfedge_handle(h);
    const FaceH f = mesh.face_handle(inner);
    const Vec3 a = pointOf(mesh, mesh.from_vertex_handle(h)), b = pointOf(mesh, mesh.to_vertex_handle(h));
    const Vec3 c = pointOf(mesh, mesh.to_vertex_handle(mesh.next_halfedge_handle(inner)));
    const Vec3 faceNormal = cross(b - a, c - a);
    Vec3 n = cross(b - a, faceNormal);
    const double len = norm(n);
    if (!(len > 0) || !f.is_valid()) continue;
    n = n * (1 / len);
    const double edge2 = dot(b - a, b - a);
    const Quadric q = Quadric::plane(n, -dot(n, a), kBoundaryWeight * edge2);
    quadric[mesh.from_vertex_handle(h).idx()] += q;
    quadric[mesh.to_vertex_handle(h).idx()] += q;
  }
}

// The targets v may weld into (on a boundary, its boundary neighbours) within the error bound, in
// the ring's order; `points` holds the ring's positions. Returns how many.
std::size_t WeldRanker::weldOptions(VertexH v, const OneRing& ring, const Vec3* points, WeldOption* options) const {
  const std::size_t k = ring.vertices.size();
  const Vec3 pv = pointOf(mesh_, v);
  std::size_t count = 0;
  auto rank = [&](std::size_t t) {
    const Quadric q = quadric_[v.idx()] + quadric_[ring.vertices[t].idx()];
    const double cost = std::max(0.0, q.error(points[t]));
    if (cost > options_.maxError * options_.maxError * q.weight) return;
    const Vec3 d = points[t] - pv;
    options[count++] = {cost, dot(d, d), q.weight, t};
  };
  if (ring.boundary) {
    rank(0);
    rank(k - 1);
  } else {
    for (std::size_t t = 0; t < k; ++t) rank(t);
  }
  return count;
}

// weldOptions, cheapest first.
std::size_t WeldRanker::rankTargets(VertexH v, const OneRing& ring, const Vec3* points, WeldOption* options) const {
  const std::size_t count = weldOptions(v, ring, points, options);
  std::sort(options, options + count);
  return count;
}

bool WeldRanker::bound(VertexH v, Candidate& lower, RankScratch& scratch) const {
  OneRing& ring = scratch.ring;
  oneRing(mesh_, v, ring);
  const std::size_t k = ring.vertices.size();
  if (k < 3 || k > kMaxDegree || ring.faces.size() < 2) return false;
  Vec3 points[kMaxDegree];
  for (std::size_t i = 0; i < k; ++i) points[i] = pointOf(mesh_, ring.vertices[i]);
  WeldOption options[kMaxDegree];
  const std::size_t count = weldOptions(v, ring, points, options);
  if (count == 0) return false;
  // Only the cheapest is needed (no sort); its target is a guess, replaced by the full ranking.
  const WeldOption& cheapest = *std::min_element(options, options + count);
  lower = {cheapest.cost, std::uint32_t(v.idx()), std::uint32_t(ring.vertices[cheapest.t].idx()), false};
  return true;
}

bool WeldRanker::evaluate(VertexH v, Candidate& best, RankScratch& scratch) const {
  OneRing& ring = scratch.ring;
  oneRing(mesh_, v, ring);
  const std::size_t k = ring.vertices.size();
  if (k < 3 || ring.faces.size() < 2) return false;
  std::vector<Vec2>& plane = scratch.plane;
  if (!exponentialMap(mesh_, v, ring, plane)) return false;
  double maxR2 = 0;
  for (const Vec2& p : plane) maxR2 = std::max(maxR2, p.x * p.x + p.y * p.y);
  const Vec3 pv = pointOf(mesh_, v);
  Vec3 points[kMaxDegree], oldNormal[kMaxDegree];  // exponentialMap refuses larger rings
  double oldLength[kMaxDegree];
  for (std::size_t i = 0; i < k; ++i) points[i] = pointOf(mesh_, ring.vertices[i]);
  for (std::size_t i = 0; i < ring.faces.size(); ++i) {
    oldNormal[i] = cross(points[i] - pv, points[(i + 1) % k] - pv);
    oldLength[i] = norm(oldNormal[i]);
  }

  // Rank the candidates by cost first (cheap), then take the cheapest that passes the checks.
  WeldOption options[kMaxDegree];
  const std::size_t count = rankTargets(v, ring, points, options);
  if (!starIsValid(plane, ring.boundary)) return false;
  const std::vector<std::uint32_t>& refused = refused_[v.idx()];
  WeldPlan plan;
  // planWeld decides bijectivity exactly; the fan must also keep some area in the plane (a sliver
  // makes the weights of the points in it ill-conditioned) and not turn over in space.
  auto valid = [&](std::size_t t) {
    if (std::find(refused.begin(), refused.end(), std::uint32_t(ring.vertices[t].idx())) != refused.end()) return false;
    if (!planWeld(plane, ring.boundary, t, plan)) return false;
    const Vec3& pu = points[t];
    for (std::size_t i = 0; i < ring.faces.size(); ++i) {
      const std::size_t j = i, j1 = (i + 1) % k;
      if (j == t || j1 == t) continue;
      if (!(orient2(plane[t], plane[j], plane[j1]) > 1e-10 * maxR2)) return false;
      const Vec3 nNew = cross(points[j] - pu, points[j1] - pu);
      const double lNew = norm(nNew);
      if (!(lNew > 1e-12 * maxR2) || dot(nNew, oldNormal[i]) < 0.1 * lNew * oldLength[i]) return false;
    }
    return true;
  };
  if (!measuring_) {
    for (std::size_t i = 0; i < count; ++i) {
      const VertexH u = ring.vertices[options[i].t];
      if (!valid(options[i].t) || !canWeldInto(mesh_, v, u, &degrees_)) continue;
      best = {options[i].cost, std::uint32_t(v.idx()), std::uint32_t(u.idx())};
      return true;
    }
    return false;
  }

  // Measuring: the cost is the weld's largest distance (weldDistance2) plus a share of the quadric's
  // mean, over the quadric's kMeasuredTargets best valid targets.
  std::vector<FanPoint>& dense = scratch.dense;
  ringPoints(mesh_, facePoints_, v, ring, plane, dense, nullptr);
  bool found = false;
  // Valid targets, whether measured or refused by canWeldInto: the same targets as when the
  // measuring came first.
  std::size_t considered = 0;
  for (std::size_t i = 0; i < count && considered < kMeasuredTargets; ++i) {
    const std::size_t t = options[i].t;
    if (!valid(t)) continue;
    ++considered;
    const VertexH u = ring.vertices[t];
    if (!canWeldInto(mesh_, v, u, &degrees_)) continue;  // cheaper than measuring, so first
    const double weight = options[i].weight;  // 0 where every face is degenerate
    const double mean = weight > 0 ? kQuadricShare * options[i].cost / weight : 0;
    const double bound = found ? best.cost - mean : std::numeric_limits<double>::infinity();
    // The fan left behind: the ring from t's successor round to its predecessor (on a boundary the
    // ring is open and t one of its ends).
    FanPoint rim[kMaxDegree];
    std::size_t rimSize = 0;
    for (std::size_t j = 1; j < k; ++j) {
      const std::size_t r = ring.boundary ? (t == 0 ? j : j - 1) : (t + j) % k;
      rim[rimSize++] = {points[r], plane[r]};
    }
    const double distance2 = weldDistance2({points[t], plane[t]}, {rim, rimSize}, dense, bound);
    if (distance2 >= bound) continue;
    best = {distance2 + mean, std::uint32_t(v.idx()), std::uint32_t(u.idx())};
    found = true;
  }
  return found;
}

}  // namespace isoatlas::multires::simplify
