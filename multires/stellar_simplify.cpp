#include "multires/stellar_simplify.h"

#include <algorithm>
#include <chrono>
#include <span>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_invoke.h>

#include "core/error.h"
#include "core/huge_pages.h"
#include "core/progress.h"
#include "multires/compact_base.h"
#include "multires/exponential_map.h"
#include "multires/mapped_points.h"
#include "multires/parallel_for_each.h"
#include "multires/quadric.h"
#include "multires/weld_batch.h"
#include "multires/weld_fan_checks.h"
#include "multires/weld_history.h"
#include "multires/weld_plan.h"
#include "multires/weld_ranking.h"

// The simplifier's driver: it ranks every vertex's cheapest weld (weld_ranking.h), takes batches of
// disjoint ones (weld_batch.h), checks them against the dense points they map again
// (weld_fan_checks.h), applies them, records them in the history (weld_history.h) and ranks their
// regions again, then compacts the result into the base mesh (compact_base.h).
namespace isoatlas::multires {
namespace {

using namespace simplify;

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
  using FanFace = simplify::FanFace;
  std::vector<FanFace> fan;
  WeldCounts operators;
  std::vector<VertexH> changed;
};

class Simplifier {
public:
  Simplifier(const Mesh& dense, const SimplifyOptions& options)
      : options_(options), dense_(dense), mesh_(toStellarMesh(dense, "simplify")), heap_(mesh_.n_vertices()) {}

  BaseMesh run(SimplifyStats& stats);

private:
  void rankAgain(std::span<const VertexH> vertices);
  std::size_t takeBatch(std::size_t most);
  void checkWeld(CheckedWeld& weld, RankScratch& scratch) const;
  void applyWeld(CheckedWeld& weld);
  void recordWeld(const CheckedWeld& weld);
  std::size_t weldBatch(std::size_t taken);

  SimplifyOptions options_;
  const Mesh& dense_;
  StellarMesh mesh_;
  DenseStars denseStars_;
  HistoryRecorder history_;  // the parametrisation's history, each face's version and its corners
  RefusedTargets refused_;   // per vertex, targets refused since its ring last changed
  RefusalCounts refusals_;
  HugePageVector<Quadric> quadric_;  // read for every neighbour of every vertex ranked
  FacePoints facePoints_;  // removed dense vertices mapped into each face
  DegreeTable degrees_;  // kept by weldInto; spares canWeldInto walks round far vertices
  CandidateHeap heap_;
  WeldCounts operators_;
  tbb::enumerable_thread_specific<RankScratch> rankScratch_;  // reused to avoid allocations
  // Ranks by the quadric, or by measured distance near the target size (ranker_.measuring()).
  WeldRanker ranker_{mesh_, quadric_, refused_, degrees_, facePoints_, options_};
  WeldBatcher batcher_{mesh_, ranker_, heap_, rankScratch_};  // owns takeBatch's marks and scratch
  std::vector<std::pair<Candidate, bool>> rankings_;            // scratch for rankAgain
  std::vector<CheckedWeld> batch_;                              // the welds of one batch, reused
  std::vector<VertexH> changed_;                                // scratch for weldBatch
};

// Ranks the vertices again (bounds them, while ranking by the quadric): each one's entry in the heap
// is replaced, or dropped when no weld of it is valid. The rankings only read the mesh, so measured
// ones (and long lists) run in parallel; the heap then changes in the list's order, so the welds do
// not depend on the thread count.
void Simplifier::rankAgain(std::span<const VertexH> vertices) {
  rankings_.resize(vertices.size());
  auto rank = [&](std::size_t i) {
    fetchAhead(mesh_, i, vertices.size(), [&](std::size_t j) { return vertices[j]; });
    RankScratch& scratch = rankScratch_.local();
    auto& [c, valid] = rankings_[i];
    valid = ranker_.measuring() ? ranker_.evaluate(vertices[i], c, scratch) : ranker_.bound(vertices[i], c, scratch);
  };
  constexpr std::size_t kParallelBounds = 256;  // bounds are cheap: a thread's start costs more
  forEach(vertices.size(), ranker_.measuring() || vertices.size() >= kParallelBounds, rank);
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
  ringPoints(mesh_, facePoints_, v, ring, weld.plane, weld.points, &weld.region);
  const bool located = locateInFan(v, ring, weld.plane, weld.plan, weld.points, weld.region, weld.hits);
  if (!located) weld.outcome = CheckedWeld::Outcome::PointOutside;
  else if (!denseTrianglesTurnLeft(denseStars_, mesh_.n_vertices(), weld.points, weld.region, ring, weld.plane,
                                   scratch.regionIndex, scratch.regionPlane))
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

// The step of an applied weld into the history (HistoryRecorder::recordWeld), and its operators into
// the counts.
void Simplifier::recordWeld(const CheckedWeld& weld) {
  history_.recordWeld(weld.ring, weld.plane, VertexH(int(weld.candidate.vertex)), weld.fan);
  operators_ += weld.operators;
}

// Takes the next batch of disjoint cheapest welds (WeldBatcher::take) into batch_. Returns how many
// were taken.
std::size_t Simplifier::takeBatch(std::size_t most) {
  const std::span<const Candidate> taken = batcher_.take(most);
  for (std::size_t i = 0; i < taken.size(); ++i) {
    if (batch_.size() <= i) batch_.emplace_back();
    batch_[i].candidate = taken[i];
  }
  return taken.size();
}

// Welds the batch's first `taken` welds: checked and applied side by side (their regions are
// disjoint), recorded in the batch's order; a weld refused or gone stale ranks its vertex again, as
// do the welds' changed vertices. Returns how many welded.
std::size_t Simplifier::weldBatch(std::size_t taken) {
  forEach(taken, true, [&](std::size_t i) {
    fetchAhead(mesh_, i, taken, [&](std::size_t j) { return VertexH(int(batch_[j].candidate.vertex)); });
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
  initQuadrics(mesh_, quadric_);
  degrees_ = degreeTable(mesh_);
  denseStars_ = DenseStars(dense_);
  history_.start(dense_, mesh_.n_faces(), n > target ? n - target : 0);
  refused_.assign(n, {});
  batcher_.start(n);
  facePoints_.assign(mesh_.n_faces(), {});

  std::size_t alive = n;
  Progress progress("simplify", n > target ? n - target : 0, "vertices");
  const auto measureFrom = std::size_t(kMeasureFromTimesTarget * double(target));
  ranker_.setMeasuring(n <= measureFrom);
  std::vector<VertexH> all(mesh_.vertices().begin(), mesh_.vertices().end());
  rankAgain(all);
  std::size_t reported = 0;
  while (alive > target && !heap_.empty()) {
    if (!ranker_.measuring() && alive <= measureFrom) {
      ranker_.setMeasuring(true);
      all.assign(mesh_.vertices().begin(), mesh_.vertices().end());
      rankAgain(all);  // by the new cost
    }
    // Never past the target, nor past the size where the ranking changes.
    alive -= weldBatch(takeBatch(std::min(kBatch, alive - (ranker_.measuring() ? target : measureFrom))));
    if ((n - alive) / 4096 != reported) progress.update(n - alive), reported = (n - alive) / 4096;
  }
  progress.update(n - alive);
  progress.finish();

  BaseMesh base = compactBase(mesh_, history_, facePoints_);
  stats.denseVertices = n;
  stats.baseVertices = base.vertexCount();
  stats.baseTriangles = base.triangleCount();
  stats.targetVertices = target;
  stats.operators = operators_;
  stats.refusals = refusals_;
  stats.historySteps = history_.history()->steps();
  stats.historyBytes = history_.history()->bytes();
  stats.reachedTarget = alive <= target;
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return base;
}

// `ratio` of n vertices, rounded.
std::size_t share(double ratio, std::size_t n) { return std::size_t(std::llround(ratio * double(n))); }

}  // namespace

std::size_t defaultBaseVertices(std::size_t denseVertices) {
  return denseVertices <= kWholeMeshMostVertices ? denseVertices : simplifiedBaseVertices(denseVertices);
}

std::size_t simplifiedBaseVertices(std::size_t denseVertices) {
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
