#include "multires/stellar_simplify.h"

#include <algorithm>
#include <chrono>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "core/error.h"
#include "core/huge_pages.h"
#include "core/progress.h"
#include "multires/exact_orientation.h"
#include "multires/exponential_map.h"
#include "multires/indexed_heap.h"
#include "multires/weld_plan.h"
#include "multires/weld_distance.h"
#include "multires/quadric.h"

namespace isoatlas::multires {
namespace {

// Near the target size the quadric's mean squared distance is a poor guide to the largest distance
// a base mesh is judged by (PSNR from the Hausdorff distance): there the welds are ranked by their
// measured distance (weldDistance2) plus this share of the quadric's mean. Measured on 13 meshes of
// data/meshes at 1 %: from 10 x the target size, the 2 best targets by quadric, share 0.5, base PSNR
// went from 0.9-4.9 dB below CGAL's optimal-placement edge collapse to 3.9 above .. 0.5 below (12 of
// 13 above; bench/RESULTS.md) for about 1.2 x the simplify time; measuring every target from the
// start cost 3 x.
constexpr double kMeasureFromTimesTarget = 10;
constexpr std::size_t kMeasuredTargets = 2;
constexpr double kQuadricShare = 0.5;

// The welds are taken in batches of up to this many of the cheapest, whose regions do not touch, so
// that their checks and rankings run side by side. The batches depend on the heap alone, never on the
// thread count, so neither does the base mesh.
constexpr std::size_t kBatch = 64;

// f(i) for every i < n: side by side when `parallel` (the results must not depend on the order).
template <class F>
void forEach(std::size_t n, bool parallel, const F& f) {
  if (parallel && n > 1)
    tbb::parallel_for(std::size_t(0), n, f);
  else
    for (std::size_t i = 0; i < n; ++i) f(i);
}

// A removed dense vertex where it lies: weights of the vertices of the face that holds it. Each face
// keeps its points together, with their positions, so that a ring's points are read in sequence.
struct MappedPoint {
  std::uint32_t id;  // the dense vertex
  std::array<int, 3> vertices;
  std::array<double, 3> bary;
  Vec3 position;
};

// A vertex's cheapest weld. The heap holds at most one per vertex, replaced when it is ranked again (a heap
// of every ranking ever made grew to 12 million entries on a 3-million-triangle mesh, and its cache
// misses took a sixth of the time). While ranking by the quadric, a vertex whose ring changed is only
// bounded: its cheapest target's cost before any check, which no valid weld of it undercuts. It is
// ranked in full when it reaches the front, so the welds come in the same order as if every vertex
// were ranked in full each time its ring changed, for a ninth of the rankings.
struct Candidate {
  double cost;
  std::uint32_t vertex, target;
  bool ranked = true;  // cost is that of its cheapest valid weld, into target; else a lower bound
};

struct CandidateVertex {
  std::size_t operator()(const Candidate& c) const { return c.vertex; }
};
struct CheaperCandidate {
  bool operator()(const Candidate& a, const Candidate& b) const {
    return a.cost != b.cost ? a.cost < b.cost : a.vertex < b.vertex;
  }
};
using CandidateHeap = IndexedHeap<Candidate, CandidateVertex, CheaperCandidate>;

// A target of a vertex's weld, by its quadric cost.
struct WeldOption {
  double cost, length2;  // ties (flat regions cost nothing) go to the nearer neighbour
  double weight;         // the quadric's: cost / weight is its mean squared distance
  std::size_t t;         // the target's place in the ring
  bool operator<(const WeldOption& o) const { return cost != o.cost ? cost < o.cost : length2 < o.length2; }
};

// Scratch space of one ranking or weld check, one per thread (they run in parallel).
struct RankScratch {
  OneRing ring;
  std::vector<Vec2> plane;
  std::vector<FanPoint> dense;
  std::vector<std::int32_t> regionIndex;  // per dense vertex, its place in a weld's points; -1 elsewhere
  std::vector<Vec2> regionPlane;
};

// A weld checked against the mesh as it stands (a check only reads, so a batch's checks run side by
// side), with what applying it needs.
struct CheckedWeld {
  enum class Outcome { Stale, PointOutside, DenseTriangle, Valid };
  Candidate candidate;
  Outcome outcome = Outcome::Stale;
  OneRing ring;
  std::vector<Vec2> plane;
  WeldPlan plan;
  std::vector<FanPoint> points;
  std::vector<MappedPoint> region;
  std::vector<TriangleHit> hits;
  // Filled by applying it: the fan's faces (each with its corners, and those as ring indices, v's
  // being k), the operators used, and u and its ring, to be ranked again.
  struct FanFace {
    FaceH face;
    std::array<int, 3> corners;
    std::array<std::uint8_t, 3> local;
  };
  std::vector<FanFace> fan;
  WeldCounts operators;
  std::vector<VertexH> changed;
};

// Per dense vertex, the other two corners of each dense face around it, in the face's order: a weld's
// check of the dense triangles reads them in sequence.
struct DenseStars {
  std::vector<std::uint32_t> offsets;
  std::vector<std::array<std::uint32_t, 2>> opposite;

  explicit DenseStars(const Mesh& dense = {}) {
    const Rows faces = vertexFaces(dense.vertexCount(), dense.faceCount(), [&](std::size_t f) { return dense.face(f); });
    offsets = faces.offsets;
    opposite.resize(faces.items.size());
    for (std::size_t a = 0; a + 1 < offsets.size(); ++a)
      for (std::uint32_t j = offsets[a]; j < offsets[a + 1]; ++j) {
        const auto c = dense.face(faces.items[j]);
        const std::size_t at = c[0] == a ? 0 : c[1] == a ? 1 : 2;
        opposite[j] = {c[(at + 1) % 3], c[(at + 2) % 3]};
      }
  }
  std::span<const std::array<std::uint32_t, 2>> of(std::uint32_t v) const {
    return {opposite.data() + offsets[v], offsets[v + 1] - offsets[v]};
  }
};

class Simplifier {
public:
  Simplifier(const Mesh& dense, const SimplifyOptions& options)
      : options_(options), dense_(dense), mesh_(toStellarMesh(dense, "simplify")), heap_(mesh_.n_vertices()) {}

  BaseMesh run(SimplifyStats& stats);

private:
  void initQuadrics();
  bool evaluate(VertexH v, Candidate& best, RankScratch& scratch) const;
  bool bound(VertexH v, Candidate& lower, RankScratch& scratch) const;
  std::size_t weldOptions(VertexH v, const OneRing& ring, const Vec3* points, WeldOption* options) const;
  std::size_t rankTargets(VertexH v, const OneRing& ring, const Vec3* points, WeldOption* options) const;
  void ringPoints(VertexH v, const OneRing& ring, const std::vector<Vec2>& plane, std::vector<FanPoint>& points,
                  std::vector<MappedPoint>* region) const;
  template <class VertexAt>
  void fetchAhead(std::size_t i, std::size_t n, const VertexAt& vertexAt) const;
  void rankAgain(std::span<const VertexH> vertices);
  std::size_t takeBatch(std::size_t most);
  void weldRegion(VertexH v, VertexH u, std::vector<VertexH>& region) const;
  bool touchesBatch(const std::vector<VertexH>& region);
  void checkWeld(CheckedWeld& weld, RankScratch& scratch) const;
  void applyWeld(CheckedWeld& weld);
  void recordWeld(const CheckedWeld& weld);
  std::size_t weldBatch(std::size_t taken);
  bool locateInFan(VertexH v, const OneRing& ring, const std::vector<Vec2>& plane, const WeldPlan& plan,
                   const std::vector<FanPoint>& points, const std::vector<MappedPoint>& region,
                   std::vector<TriangleHit>& hits) const;
  bool denseTrianglesTurnLeft(const std::vector<FanPoint>& points, const std::vector<MappedPoint>& region,
                              const OneRing& ring, const std::vector<Vec2>& plane, RankScratch& scratch) const;
  void recordStep(const OneRing& ring, const std::vector<Vec2>& plane, VertexH v);
  BaseMesh compact();

  SimplifyOptions options_;
  const Mesh& dense_;
  StellarMesh mesh_;
  DenseStars denseStars_;
  std::shared_ptr<ParametrisationHistory> history_;
  std::vector<std::uint32_t> faceVersion_;              // per face, its version in history_
  std::vector<std::array<int, 3>> faceCorners_;         // per face, its version's corners in order
  std::vector<std::vector<std::uint32_t>> refused_;     // per vertex, targets refused since its ring last changed
  RefusalCounts refusals_;
  HugePageVector<Quadric> quadric_;  // read for every neighbour of every vertex ranked
  bool measuring_ = false;  // ranking by measured distance (near the target size) instead of the quadric
  std::vector<std::vector<MappedPoint>> facePoints_;  // removed dense vertices mapped into each face
  DegreeTable degrees_;  // kept by weldInto; spares canWeldInto walks round far vertices
  CandidateHeap heap_;
  WeldCounts operators_;
  tbb::enumerable_thread_specific<RankScratch> rankScratch_;  // reused to avoid allocations
  std::vector<std::pair<Candidate, bool>> rankings_;            // scratch for rankAgain
  std::vector<Candidate> popped_;                               // scratch for takeBatch
  struct PoppedWeld {
    Candidate candidate;  // ranked in full
    bool valid = false;
    std::vector<VertexH> region;
  };
  std::vector<PoppedWeld> poppedRanked_;                        // scratch for takeBatch
  std::vector<CheckedWeld> batch_;                              // the welds of one batch, reused
  std::vector<std::uint32_t> batchMark_;                        // per vertex, the last batch whose region held it
  std::uint32_t batchStamp_ = 0;
  std::vector<VertexH> changed_;                                // scratch for weldBatch
};

Vec3 pointOf(const StellarMesh& mesh, VertexH v) { return toVec3(mesh.point(v)); }

// A vertex's local index in a weld's layout: ring vertex i is i, the removed vertex v is k.
std::uint8_t layoutIndex(const OneRing& ring, VertexH v, int vertex) {
  const std::size_t k = ring.vertices.size();
  if (vertex == v.idx()) return std::uint8_t(k);
  for (std::size_t i = 0; i < k; ++i)
    if (ring.vertices[i].idx() == vertex) return std::uint8_t(i);
  throw Error("stellar simplify: a face of the 1-ring has a corner outside it", ErrorKind::Failure);
}

void Simplifier::initQuadrics() {
  quadric_.assign(mesh_.n_vertices(), {});
  for (const FaceH f : mesh_.faces()) {
    Vec3 p[3];
    int i = 0;
    for (const VertexH v : mesh_.fv_range(f)) p[i++] = pointOf(mesh_, v);
    const Vec3 n = cross(p[1] - p[0], p[2] - p[0]);
    const double twiceArea = norm(n);
    if (!(twiceArea > 0)) continue;
    const Vec3 unit = n * (1 / twiceArea);
    const Quadric q = Quadric::plane(unit, -dot(unit, p[0]), twiceArea / 6);  // a third of the area each
    for (const VertexH v : mesh_.fv_range(f)) quadric_[v.idx()] += q;
  }
  // Boundary edges: a plane through the edge, perpendicular to its face, weighted strongly so welds
  // along the boundary keep its course.
  constexpr double kBoundaryWeight = 10;
  for (const HalfedgeH h : mesh_.halfedges()) {
    if (!mesh_.is_boundary(h)) continue;
    const HalfedgeH inner = mesh_.opposite_halfedge_handle(h);
    const FaceH f = mesh_.face_handle(inner);
    const Vec3 a = pointOf(mesh_, mesh_.from_vertex_handle(h)), b = pointOf(mesh_, mesh_.to_vertex_handle(h));
    const Vec3 c = pointOf(mesh_, mesh_.to_vertex_handle(mesh_.next_halfedge_handle(inner)));
    const Vec3 faceNormal = cross(b - a, c - a);
    Vec3 n = cross(b - a, faceNormal);
    const double len = norm(n);
    if (!(len > 0) || !f.is_valid()) continue;
    n = n * (1 / len);
    const double edge2 = dot(b - a, b - a);
    const Quadric q = Quadric::plane(n, -dot(n, a), kBoundaryWeight * edge2);
    quadric_[mesh_.from_vertex_handle(h).idx()] += q;
    quadric_[mesh_.to_vertex_handle(h).idx()] += q;
  }
}

// The targets v may weld into (on a boundary, its boundary neighbours) within the error bound, in
// the ring's order; `points` holds the ring's positions. Returns how many.
std::size_t Simplifier::weldOptions(VertexH v, const OneRing& ring, const Vec3* points, WeldOption* options) const {
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
std::size_t Simplifier::rankTargets(VertexH v, const OneRing& ring, const Vec3* points, WeldOption* options) const {
  const std::size_t count = weldOptions(v, ring, points, options);
  std::sort(options, options + count);
  return count;
}

// A lower bound of v's cheapest valid weld while ranking by the quadric: its cheapest target before
// the checks (evaluate's first option). False where evaluate would find no weld for want of targets.
bool Simplifier::bound(VertexH v, Candidate& lower, RankScratch& scratch) const {
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

// The cheapest valid weld of v: into which neighbour, at what quadric cost. A weld is valid when the
// fan it leaves is counter-clockwise in v's exponential map (so the parametrisation stays one-to-one),
// no face turns over in space, and the topology is kept (canWeldInto).
bool Simplifier::evaluate(VertexH v, Candidate& best, RankScratch& scratch) const {
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
  ringPoints(v, ring, plane, dense, nullptr);
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

// The points a weld of v maps again: v and every dense vertex mapped into its ring's faces, in space
// and in the ring's flat map `plane`; `region`, when given, gets where they lie now (v: at itself).
void Simplifier::ringPoints(VertexH v, const OneRing& ring, const std::vector<Vec2>& plane,
                            std::vector<FanPoint>& points, std::vector<MappedPoint>* region) const {
  const Vec3 pv = pointOf(mesh_, v);
  points.assign(1, {pv, {0, 0}});
  if (region) region->assign(1, {std::uint32_t(v.idx()), {v.idx(), v.idx(), v.idx()}, {1, 0, 0}, pv});
  const std::size_t k = ring.vertices.size();
  // The faces' lists lie far apart in memory: their first lines are fetched all at once.
  for (const FaceH f : ring.faces) __builtin_prefetch(&facePoints_[f.idx()]);
  for (const FaceH f : ring.faces)
    if (!facePoints_[f.idx()].empty()) __builtin_prefetch(facePoints_[f.idx()].data());
  for (std::size_t i = 0; i < ring.faces.size(); ++i) {
    // A point of ring face i is weighted on that face's corners: v, ring vertex i and i + 1.
    auto planeOf = [&](int vertex) {
      return vertex == v.idx() ? Vec2{0, 0} : vertex == ring.vertices[i].idx() ? plane[i] : plane[(i + 1) % k];
    };
    for (const MappedPoint& m : facePoints_[ring.faces[i].idx()]) {
      points.push_back({m.position, planeOf(m.vertices[0]) * m.bary[0] + planeOf(m.vertices[1]) * m.bary[1] +
                                        planeOf(m.vertices[2]) * m.bary[2]});
      if (region) region->push_back(m);
    }
  }
}

// The vertices a batch ranks or checks lie far apart: while vertex i of n is worked on, the records
// a walk round the next ones starts from are fetched, two ahead the vertex's, one ahead its first
// halfedge's (whose handle the vertex's holds).
template <class VertexAt>
void Simplifier::fetchAhead(std::size_t i, std::size_t n, const VertexAt& vertexAt) const {
  if (i + 2 < n) __builtin_prefetch(&mesh_.vertex(vertexAt(i + 2)));
  if (i + 1 < n)
    if (const HalfedgeH h = mesh_.halfedge_handle(vertexAt(i + 1)); h.is_valid()) __builtin_prefetch(&mesh_.halfedge(h));
}

// Ranks the vertices again (bounds them, while ranking by the quadric): each one's entry in the heap
// is replaced, or dropped when no weld of it is valid. The rankings only read the mesh, so measured
// ones (and long lists) run in parallel; the heap then changes in the list's order, so the welds do
// not depend on the thread count.
void Simplifier::rankAgain(std::span<const VertexH> vertices) {
  rankings_.resize(vertices.size());
  auto rank = [&](std::size_t i) {
    fetchAhead(i, vertices.size(), [&](std::size_t j) { return vertices[j]; });
    RankScratch& scratch = rankScratch_.local();
    auto& [c, valid] = rankings_[i];
    valid = measuring_ ? evaluate(vertices[i], c, scratch) : bound(vertices[i], c, scratch);
  };
  constexpr std::size_t kParallelBounds = 256;  // bounds are cheap: a thread's start costs more
  forEach(vertices.size(), measuring_ || vertices.size() >= kParallelBounds, rank);
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (rankings_[i].second)
      heap_.set(rankings_[i].first);
    else
      heap_.erase(std::size_t(vertices[i].idx()));
  }
}

// Checks the weld of the candidate's vertex v into its target u against the mesh as it stands: u
// still a neighbour it may weld into (else Stale: v is ranked again), the plan (evaluate() checked it
// on this very ring: any change to the ring ranks v again), every dense point of the ring found in
// the new fan by exact location, and no dense triangle inside the ring clockwise in its layout.
void Simplifier::checkWeld(CheckedWeld& weld, RankScratch& scratch) const {
  const VertexH v(int(weld.candidate.vertex)), u(int(weld.candidate.target));
  weld.outcome = CheckedWeld::Outcome::Stale;
  if (mesh_.status(u).deleted() || !canWeldInto(mesh_, v, u, &degrees_)) return;
  OneRing& ring = weld.ring;
  oneRing(mesh_, v, ring);
  const std::size_t k = ring.vertices.size();
  exponentialMap(mesh_, v, ring, weld.plane);
  const std::size_t t = std::size_t(std::find(ring.vertices.begin(), ring.vertices.end(), u) - ring.vertices.begin());
  if (t == k || !planWeld(weld.plane, ring.boundary, t, weld.plan))
    throw Error("stellar simplify: a weld ranked valid has no valid plan", ErrorKind::Failure);
  ringPoints(v, ring, weld.plane, weld.points, &weld.region);
  const bool located = locateInFan(v, ring, weld.plane, weld.plan, weld.points, weld.region, weld.hits);
  if (!located) weld.outcome = CheckedWeld::Outcome::PointOutside;
  else if (!denseTrianglesTurnLeft(weld.points, weld.region, ring, weld.plane, scratch))
    weld.outcome = CheckedWeld::Outcome::DenseTriangle;
  else weld.outcome = CheckedWeld::Outcome::Valid;
}

// Applies a valid checked weld to the mesh and gives the new fan's faces their dense points. It
// writes only v's and u's regions, so the disjoint welds of a batch apply side by side; their history
// is recorded after (recordWeld), in the batch's order.
void Simplifier::applyWeld(CheckedWeld& weld) {
  const VertexH v(int(weld.candidate.vertex)), u(int(weld.candidate.target));
  const OneRing& ring = weld.ring;
  const WeldPlan& plan = weld.plan;
  const std::size_t t = plan.target;
  for (const FaceH f : ring.faces) facePoints_[f.idx()].clear();
  VertexH spokes[kMaxDegree];
  for (std::size_t i = 0; i < plan.flipCount; ++i) spokes[i] = ring.vertices[plan.flips[i]];
  weld.operators = weldInto(mesh_, v, u, &degrees_, {spokes, plan.flipCount});

  // The faces left where the ring was are the plan's fan, in the ring's order (its history's order).
  std::size_t rimPosition[kMaxDegree];
  for (std::size_t m = 0; m < plan.rimSize; ++m) rimPosition[plan.rim[m]] = m;
  FaceH fan[kMaxDegree];
  weld.fan.clear();
  for (const FaceH f : ring.faces) {
    if (mesh_.status(f).deleted()) continue;
    CheckedWeld::FanFace face{f, {}, {}};
    std::size_t first = kMaxDegree;
    int i = 0;
    for (const VertexH w : mesh_.fv_range(f)) {
      face.corners[i] = w.idx();
      face.local[i] = layoutIndex(ring, v, w.idx());
      if (face.local[i] != t) first = std::min(first, rimPosition[face.local[i]]);
      ++i;
    }
    fan[first] = f;
    weld.fan.push_back(face);
  }
  for (std::size_t i = 0; i < weld.points.size(); ++i) {
    const std::size_t m = weld.hits[i].triangle;
    const FaceH f = fan[m];
    facePoints_[f.idx()].push_back({weld.region[i].id,
                                    {u.idx(), ring.vertices[plan.rim[m]].idx(), ring.vertices[plan.rim[m + 1]].idx()},
                                    weld.hits[i].bary, weld.points[i].position});
  }

  quadric_[u.idx()] += quadric_[v.idx()];
  weld.changed.assign(1, u);
  for (const VertexH w : mesh_.vv_range(u)) weld.changed.push_back(w);
  for (const VertexH w : weld.changed) refused_[w.idx()].clear();
}

// The step of an applied weld into the history: the faces it replaced (their versions still those
// before it), then a new version for each face of its fan.
void Simplifier::recordWeld(const CheckedWeld& weld) {
  recordStep(weld.ring, weld.plane, VertexH(int(weld.candidate.vertex)));
  for (const CheckedWeld::FanFace& face : weld.fan) {
    faceVersion_[face.face.idx()] = history_->adds(face.local);
    faceCorners_[face.face.idx()] = face.corners;
  }
  operators_ += weld.operators;
}

// The vertices the weld of v into u reads or writes: v, u and their rings.
void Simplifier::weldRegion(VertexH v, VertexH u, std::vector<VertexH>& region) const {
  region.clear();
  for (const VertexH centre : {v, u}) {
    if (mesh_.status(centre).deleted()) continue;  // a stale target: v's check finds it so
    region.push_back(centre);
    for (const VertexH w : mesh_.vv_range(centre)) region.push_back(w);
  }
}

// Whether a weld's region holds a vertex of a weld already taken into the batch; if not, marks it
// for the batch.
bool Simplifier::touchesBatch(const std::vector<VertexH>& region) {
  for (const VertexH w : region)
    if (batchMark_[w.idx()] == batchStamp_) return true;
  for (const VertexH w : region) batchMark_[w.idx()] = batchStamp_;
  return false;
}

// Takes up to `most` of the cheapest welds whose regions do not touch into batch_, in the order the
// welds would come one at a time: the heap's front is popped (vertices only bounded are ranked in
// full, side by side, and each weld's region found); a vertex whose full ranking differs from its
// bound goes back with it, and no weld dearer than one that went back is taken; a weld touching one
// already taken goes back as it was. Returns how many were taken.
std::size_t Simplifier::takeBatch(std::size_t most) {
  popped_.clear();
  while (popped_.size() < most && !heap_.empty()) popped_.push_back(heap_.pop());
  poppedRanked_.resize(popped_.size());
  forEach(popped_.size(), true, [&](std::size_t i) {
    fetchAhead(i, popped_.size(), [&](std::size_t j) { return VertexH(int(popped_[j].vertex)); });
    auto& [c, valid, region] = poppedRanked_[i];
    c = popped_[i];
    valid = c.ranked || evaluate(VertexH(int(c.vertex)), c, rankScratch_.local());
    if (valid) weldRegion(VertexH(int(c.vertex)), VertexH(int(c.target)), region);
  });

  ++batchStamp_;
  std::size_t taken = 0;
  double wentBack = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < popped_.size(); ++i) {
    const auto& [c, valid, region] = poppedRanked_[i];
    if (!valid) continue;  // no valid weld: dropped, as when it is ranked again
    if (!popped_[i].ranked && c.cost != popped_[i].cost) {
      heap_.set(c);
      wentBack = std::min(wentBack, c.cost);
      continue;
    }
    if (c.cost > wentBack || touchesBatch(region)) {
      heap_.set(c);
      continue;
    }
    if (batch_.size() <= taken) batch_.emplace_back();
    batch_[taken++].candidate = c;
  }
  return taken;
}

// Where each point a weld maps again lies in the fan the plan leaves around ring vertex t (u):
// by exact location, or, for a point on the ring's border (no weight on v), in the fan face across
// that border edge with the same weights (its place in the plane, computed in floating point, may
// fall just outside the ring). False when a point lies in no fan face.
bool Simplifier::locateInFan(VertexH v, const OneRing& ring, const std::vector<Vec2>& plane, const WeldPlan& plan,
                             const std::vector<FanPoint>& points, const std::vector<MappedPoint>& region,
                             std::vector<TriangleHit>& hits) const {
  const std::size_t t = plan.target;
  const VertexH u = ring.vertices[t];
  const std::size_t fanFaces = plan.rimSize - 1;
  auto fanFace = [&](std::size_t m) { return std::array<Vec2, 3>{plane[t], plane[plan.rim[m]], plane[plan.rim[m + 1]]}; };
  hits.resize(points.size());
  std::size_t hint = 0;
  bool located = true;
  auto onBorder = [&](std::size_t i, TriangleHit& hit) {
    if (i == 0) return false;
    const MappedPoint& m = region[i];
    int at = -1;
    for (int c = 0; c < 3; ++c)
      if (m.vertices[c] == v.idx()) at = c;
    if (at < 0 || m.bary[at] != 0) return false;
    for (std::size_t f = 0; f < fanFaces; ++f) {
      const int corners[3] = {u.idx(), ring.vertices[plan.rim[f]].idx(), ring.vertices[plan.rim[f + 1]].idx()};
      std::array<double, 3> bary{};
      int found = 0;
      for (int c = 0; c < 3; ++c)
        for (const int e : {(at + 1) % 3, (at + 2) % 3})
          if (corners[c] == m.vertices[e]) bary[c] = m.bary[e], ++found;
      if (found == 2) {
        hit = {f, bary, true};
        return true;
      }
    }
    return false;
  };
  for (std::size_t i = 0; i < points.size() && located; ++i) {
    if (onBorder(i, hits[i])) continue;
    hits[i] = locateExactly(points[i].plane, fanFaces, fanFace, hint);
    located = hits[i].triangle != kNoTriangleHit;
    hint = located ? hits[i].triangle : 0;
  }
  return located;
}

// Whether every dense triangle with a corner among the points a weld maps again (v and the dense
// vertices mapped into its ring: inside the ring) and all its corners there or on the ring turns
// counter-clockwise in the ring's layout (exact test).
bool Simplifier::denseTrianglesTurnLeft(const std::vector<FanPoint>& points, const std::vector<MappedPoint>& region,
                                        const OneRing& ring, const std::vector<Vec2>& plane, RankScratch& scratch) const {
  std::vector<std::int32_t>& regionIndex = scratch.regionIndex;
  if (regionIndex.empty()) regionIndex.assign(mesh_.n_vertices(), -1);
  std::vector<Vec2>& at = scratch.regionPlane;
  at.clear();
  auto mark = [&](std::uint32_t vertex, const Vec2& p) {
    regionIndex[vertex] = std::int32_t(at.size());
    at.push_back(p);
  };
  // The points' dense vertices lie far apart in the tables: each one's entries are fetched a few
  // points ahead, and its star as it is marked, ahead of the test below.
  constexpr std::size_t kAhead = 8;
  for (std::size_t i = 0; i < region.size(); ++i) {
    if (i + kAhead < region.size()) {
      __builtin_prefetch(&regionIndex[region[i + kAhead].id], 1);
      __builtin_prefetch(&denseStars_.offsets[region[i + kAhead].id]);
    }
    __builtin_prefetch(denseStars_.of(region[i].id).data());
    mark(region[i].id, points[i].plane);
  }
  for (std::size_t i = 0; i < ring.vertices.size(); ++i) mark(std::uint32_t(ring.vertices[i].idx()), plane[i]);
  bool ok = true;
  for (std::size_t i = 0; i < region.size() && ok; ++i)
    for (const auto& [second, third] : denseStars_.of(region[i].id)) {
      const std::int32_t b = regionIndex[second], d = regionIndex[third];
      // Once per face inside: from its corner that comes first among the inner points.
      if (b <= std::int32_t(i) || d <= std::int32_t(i)) continue;
      if (exactOrientation(at[i], at[std::size_t(b)], at[std::size_t(d)]) <= 0) {
        ok = false;
        break;
      }
    }
  for (const MappedPoint& m : region) regionIndex[m.id] = -1;
  for (const VertexH w : ring.vertices) regionIndex[w.idx()] = -1;
  return ok;
}

// The step of removing v into the history: its ring's layout (v at local index k) and the faces it
// replaces, with their versions' corners as local indices.
void Simplifier::recordStep(const OneRing& ring, const std::vector<Vec2>& plane, VertexH v) {
  const std::size_t k = ring.vertices.size();
  Vec2 layout[kMaxDegree + 1];
  std::copy(plane.begin(), plane.end(), layout);
  layout[k] = {0, 0};
  history_->beginStep({layout, k + 1});
  for (const FaceH f : ring.faces) {
    const auto& c = faceCorners_[f.idx()];
    history_->replaces(faceVersion_[f.idx()], {layoutIndex(ring, v, c[0]), layoutIndex(ring, v, c[1]), layoutIndex(ring, v, c[2])});
  }
}

// Welds the batch's first `taken` welds: checked and applied side by side (their regions are
// disjoint), recorded in the batch's order; a weld refused or gone stale ranks its vertex again, as
// do the welds' changed vertices. Returns how many welded.
std::size_t Simplifier::weldBatch(std::size_t taken) {
  forEach(taken, true, [&](std::size_t i) {
    fetchAhead(i, taken, [&](std::size_t j) { return VertexH(int(batch_[j].candidate.vertex)); });
    checkWeld(batch_[i], rankScratch_.local());
  });
  forEach(taken, true, [&](std::size_t i) {
    if (batch_[i].outcome == CheckedWeld::Outcome::Valid) applyWeld(batch_[i]);
  });
  std::size_t welded = 0;
  changed_.clear();
  for (std::size_t i = 0; i < taken; ++i) {
    const CheckedWeld& weld = batch_[i];
    switch (weld.outcome) {
      case CheckedWeld::Outcome::Valid:
        changed_.insert(changed_.end(), weld.changed.begin(), weld.changed.end());
        ++welded;
        continue;
      case CheckedWeld::Outcome::PointOutside: ++refusals_.pointOutside; break;
      case CheckedWeld::Outcome::DenseTriangle: ++refusals_.denseTriangle; break;
      case CheckedWeld::Outcome::Stale: break;
    }
    if (weld.outcome != CheckedWeld::Outcome::Stale) refused_[weld.candidate.vertex].push_back(weld.candidate.target);
    changed_.push_back(VertexH(int(weld.candidate.vertex)));
  }
  // The history is recorded, in the batch's order, while the changed vertices are ranked again:
  // the rankings never read the history, nor the recording the mesh.
  tbb::parallel_invoke(
      [&] {
        for (std::size_t i = 0; i < taken; ++i)
          if (batch_[i].outcome == CheckedWeld::Outcome::Valid) recordWeld(batch_[i]);
      },
      [&] { rankAgain(changed_); });
  return welded;
}

BaseMesh Simplifier::run(SimplifyStats& stats) {
  const auto start = std::chrono::steady_clock::now();
  const std::size_t n = mesh_.n_vertices();
  const std::size_t target = targetBaseVertices(options_, n);
  initQuadrics();
  degrees_ = degreeTable(mesh_);
  denseStars_ = DenseStars(dense_);
  history_ = std::make_shared<ParametrisationHistory>(std::uint32_t(dense_.faceCount()));
  history_->reserve(n > target ? n - target : 0);
  faceVersion_.resize(mesh_.n_faces());
  faceCorners_.resize(mesh_.n_faces());
  for (std::uint32_t f = 0; f < dense_.faceCount(); ++f) {
    faceVersion_[f] = f;
    const auto c = dense_.face(f);
    faceCorners_[f] = {int(c[0]), int(c[1]), int(c[2])};
  }
  refused_.assign(n, {});
  batchMark_.assign(n, 0);
  facePoints_.assign(mesh_.n_faces(), {});

  std::size_t alive = n;
  Progress progress("simplify", n > target ? n - target : 0, "vertices");
  const auto measureFrom = std::size_t(kMeasureFromTimesTarget * double(target));
  measuring_ = n <= measureFrom;
  std::vector<VertexH> all(mesh_.vertices().begin(), mesh_.vertices().end());
  rankAgain(all);
  std::size_t reported = 0;
  while (alive > target && !heap_.empty()) {
    if (!measuring_ && alive <= measureFrom) {
      measuring_ = true;
      all.assign(mesh_.vertices().begin(), mesh_.vertices().end());
      rankAgain(all);  // by the new cost
    }
    // Never past the target, nor past the size where the ranking changes.
    alive -= weldBatch(takeBatch(std::min(kBatch, alive - (measuring_ ? target : measureFrom))));
    if ((n - alive) / 4096 != reported) progress.update(n - alive), reported = (n - alive) / 4096;
  }
  progress.update(n - alive);
  progress.finish();

  BaseMesh base = compact();
  stats.denseVertices = n;
  stats.baseVertices = base.vertexCount();
  stats.baseTriangles = base.triangleCount();
  stats.targetVertices = target;
  stats.operators = operators_;
  stats.refusals = refusals_;
  stats.historySteps = history_->steps();
  stats.historyBytes = history_->bytes();
  stats.reachedTarget = alive <= target;
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return base;
}

BaseMesh Simplifier::compact() {
  BaseMesh base;
  std::vector<std::uint32_t> vertexIndex(mesh_.n_vertices(), ~0u), faceIndex(mesh_.n_faces(), ~0u);
  for (const VertexH v : mesh_.vertices()) {
    vertexIndex[v.idx()] = std::uint32_t(base.positions.size());
    base.positions.push_back(pointOf(mesh_, v));
    base.denseVertex.push_back(v.idx());
  }
  for (const FaceH f : mesh_.faces()) {
    faceIndex[f.idx()] = std::uint32_t(base.triangles.size());
    std::array<std::uint32_t, 3> t{};
    HistoryFrame frame{faceVersion_[f.idx()], {}};
    int i = 0;
    for (const VertexH v : mesh_.fv_range(f)) {
      t[i] = vertexIndex[v.idx()];
      for (int j = 0; j < 3; ++j) frame.corner[i][j] = faceCorners_[f.idx()][j] == v.idx() ? 1 : 0;
      ++i;
    }
    base.triangles.push_back(t);
    base.historyFrames.push_back(frame);
  }
  base.history = history_;
  const std::size_t n = mesh_.n_vertices();
  base.denseTriangle.resize(n);
  base.denseBary.resize(n);
  for (std::size_t d = 0; d < n; ++d) {
    const VertexH v{int(d)};
    if (!mesh_.status(v).deleted()) {
      // A base vertex: a corner of any of its faces.
      const HalfedgeH h = mesh_.halfedge_handle(v);
      const FaceH f = mesh_.is_boundary(h) ? mesh_.face_handle(mesh_.opposite_halfedge_handle(h)) : mesh_.face_handle(h);
      const std::uint32_t t = faceIndex[f.idx()];
      base.denseTriangle[d] = t;
      base.denseBary[d] = {0, 0, 0};
      for (int c = 0; c < 3; ++c)
        if (base.triangles[t][c] == vertexIndex[d]) base.denseBary[d][c] = 1;
      continue;
    }
  }
  for (const FaceH f : mesh_.faces()) {
    const std::uint32_t t = faceIndex[f.idx()];
    for (const MappedPoint& m : facePoints_[f.idx()]) {
      base.denseTriangle[m.id] = t;
      for (int c = 0; c < 3; ++c)
        for (int j = 0; j < 3; ++j)
          if (base.triangles[t][c] == vertexIndex[m.vertices[j]]) base.denseBary[m.id][c] = m.bary[j];
    }
  }
  return base;
}

// `ratio` of n vertices, rounded.
std::size_t share(double ratio, std::size_t n) { return std::size_t(std::llround(ratio * double(n))); }

}  // namespace

std::size_t defaultBaseVertices(std::size_t denseVertices) {
  return std::max({std::size_t(4), share(kLargeMeshBaseRatio, denseVertices),
                   std::min(share(kSmallMeshBaseRatio, denseVertices), kSmallMeshMostBaseVertices)});
}

std::size_t targetBaseVertices(const SimplifyOptions& options, std::size_t denseVertices) {
  if (options.targetVertices > 0) return options.targetVertices;
  if (!options.vertexRatio) return defaultBaseVertices(denseVertices);
  return std::max<std::size_t>(4, share(*options.vertexRatio, denseVertices));
}

BaseMesh simplifyStellar(const Mesh& dense, const SimplifyOptions& options, SimplifyStats* stats) {
  require(!options.vertexRatio || (*options.vertexRatio > 0 && *options.vertexRatio <= 1), "simplify: the vertex ratio must be in (0, 1]");
  require(options.maxError > 0, "simplify: the error bound must be positive");
  Simplifier simplifier(dense, options);
  SimplifyStats local;
  SimplifyStats& out = stats ? *stats : local;
  return simplifier.run(out);
}

}  // namespace isoatlas::multires
