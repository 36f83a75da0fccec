// The ranking of the simplifier's welds: each vertex's quadric (Garland and Heckbert; boundary edges
// add perpendicular planes), its weld options (the targets within the error bound, by quadric cost),
// a lower bound of its cheapest valid weld and the full evaluation of that weld (by the quadric, or
// near the target size by the measured distance, weldDistance2), and the heap of the vertices'
// cheapest welds the simplifier takes them from.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/huge_pages.h"
#include "multires/indexed_heap.h"
#include "multires/mapped_points.h"
#include "multires/quadric.h"
#include "multires/stellar_operators.h"
#include "multires/stellar_simplify.h"
#include "multires/vec2.h"
#include "multires/weld_distance.h"

namespace isoatlas::multires::simplify {

// Near the target size the quadric's mean squared distance is a poor guide to the largest distance
// a base mesh is judged by (PSNR from the Hausdorff distance): there the welds are ranked by their
// measured distance (weldDistance2) plus this share of the quadric's mean. Measured on 13 meshes of
// data/meshes at 1 %: from 10 x the target size, the 2 best targets by quadric, share 0.5, base PSNR
// went from 0.9-4.9 dB below CGAL's optimal-placement edge collapse to 3.9 above .. 0.5 below (12 of
// 13 above; bench/RESULTS.md) for about 1.2 x the simplify time; measuring every target from the
// start cost 3 x.
inline constexpr double kMeasureFromTimesTarget = 10;
inline constexpr std::size_t kMeasuredTargets = 2;
inline constexpr double kQuadricShare = 0.5;

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

// Per vertex, the targets refused since its ring last changed.
using RefusedTargets = std::vector<std::vector<std::uint32_t>>;

// Input: the mesh. Output: `quadric`, per vertex the quadric of its faces' planes (a third of each
// face's area each) and of its boundary edges' perpendicular planes.
void initQuadrics(const StellarMesh& mesh, HugePageVector<Quadric>& quadric);

// Ranks a vertex's welds on the mesh as it stands. It holds references to the simplifier's state
// and only reads it, so rankings run side by side; which cost it ranks by (quadric or measured) is
// its one setting.
class WeldRanker {
public:
  WeldRanker(const StellarMesh& mesh, const HugePageVector<Quadric>& quadric, const RefusedTargets& refused,
             const DegreeTable& degrees, const FacePoints& facePoints, const SimplifyOptions& options)
      : mesh_(mesh), quadric_(quadric), refused_(refused), degrees_(degrees), facePoints_(facePoints), options_(options) {}

  bool measuring() const { return measuring_; }
  void setMeasuring(bool measuring) { measuring_ = measuring; }

  // A lower bound of v's cheapest valid weld while ranking by the quadric: its cheapest target before
  // the checks (evaluate's first option). False where evaluate would find no weld for want of targets.
  // Output: `lower` (ranked false). Scratch: `scratch`.
  bool bound(VertexH v, Candidate& lower, RankScratch& scratch) const;

  // The cheapest valid weld of v: into which neighbour, at what quadric cost. A weld is valid when the
  // fan it leaves is counter-clockwise in v's exponential map (so the parametrisation stays one-to-one),
  // no face turns over in space, and the topology is kept (canWeldInto).
  // Output: `best` (ranked), when it returns true; false when no weld of v is valid. Scratch: `scratch`.
  bool evaluate(VertexH v, Candidate& best, RankScratch& scratch) const;

private:
  std::size_t weldOptions(VertexH v, const OneRing& ring, const Vec3* points, WeldOption* options) const;
  std::size_t rankTargets(VertexH v, const OneRing& ring, const Vec3* points, WeldOption* options) const;

  const StellarMesh& mesh_;
  const HugePageVector<Quadric>& quadric_;  // read for every neighbour of every vertex ranked
  const RefusedTargets& refused_;           // per vertex, targets refused since its ring last changed
  const DegreeTable& degrees_;              // kept by weldInto; spares canWeldInto walks round far vertices
  const FacePoints& facePoints_;            // removed dense vertices mapped into each face
  const SimplifyOptions& options_;
  bool measuring_ = false;  // ranking by measured distance (near the target size) instead of the quadric
};

}  // namespace isoatlas::multires::simplify
