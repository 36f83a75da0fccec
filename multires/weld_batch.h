// WeldBatcher: takes from the heap of the vertices' cheapest welds a batch of the cheapest whose
// regions (v, its target and their rings) do not touch, in the order the welds would come one at a
// time, so that the simplifier checks, applies and ranks them again side by side.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <tbb/enumerable_thread_specific.h>

#include "multires/stellar_mesh.h"
#include "multires/weld_ranking.h"

namespace isoatlas::multires::simplify {

// The welds are taken in batches of up to this many of the cheapest, whose regions do not touch, so
// that their checks and rankings run side by side. The batches depend on the heap alone, never on the
// thread count, so neither does the base mesh.
inline constexpr std::size_t kBatch = 64;

class WeldBatcher {
public:
  // Holds references: the mesh (read), the ranker (to rank in full the vertices only bounded), the
  // heap it takes from and the rankings' per-thread scratch.
  WeldBatcher(const StellarMesh& mesh, const WeldRanker& ranker, CandidateHeap& heap,
              tbb::enumerable_thread_specific<RankScratch>& scratch)
      : mesh_(mesh), ranker_(ranker), heap_(heap), scratch_(scratch) {}

  // Sizes the marks for a mesh of `vertices` vertices (handle indices).
  void start(std::size_t vertices) { batchMark_.assign(vertices, 0); }

  // Takes up to `most` of the cheapest welds whose regions do not touch into the batch, in the order the
  // welds would come one at a time: the heap's front is popped (vertices only bounded are ranked in
  // full, side by side, and each weld's region found); a vertex whose full ranking differs from its
  // bound goes back with it, and no weld dearer than one that went back is taken; a weld touching one
  // already taken goes back as it was. Returns the welds taken (valid until the next call).
  std::span<const Candidate> take(std::size_t most);

private:
  void weldRegion(VertexH v, VertexH u, std::vector<VertexH>& region) const;
  bool touchesBatch(const std::vector<VertexH>& region);

  const StellarMesh& mesh_;
  const WeldRanker& ranker_;
  CandidateHeap& heap_;
  tbb::enumerable_thread_specific<RankScratch>& scratch_;
  std::vector<Candidate> popped_;  // scratch for take
  struct PoppedWeld {
    Candidate candidate;  // ranked in full
    bool valid = false;
    std::vector<VertexH> region;
  };
  std::vector<PoppedWeld> poppedRanked_;  // scratch for take
  std::vector<Candidate> taken_;          // the batch, reused
  std::vector<std::uint32_t> batchMark_;  // per vertex, the last batch whose region held it
  std::uint32_t batchStamp_ = 0;
};

}  // namespace isoatlas::multires::simplify
