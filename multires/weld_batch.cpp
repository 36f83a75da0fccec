#include "multires/weld_batch.h"

#include <algorithm>
#include <limits>

#include "multires/parallel_for_each.h"

namespace isoatlas::multires::simplify {

// The vertices the weld of v into u reads or writes: v, u and their rings.
void WeldBatcher::weldRegion(VertexH v, VertexH u, std::vector<VertexH>& region) const {
  region.clear();
  for (const VertexH centre : {v, u}) {
    if (mesh_.status(centre).deleted()) continue;  // a stale target: v's check finds it so
    region.push_back(centre);
    for (const VertexH w : mesh_.vv_range(centre)) region.push_back(w);
  }
}

// Whether a weld's region holds a vertex of a weld already taken into the batch; if not, marks it
// for the batch.
bool WeldBatcher::touchesBatch(const std::vector<VertexH>& region) {
  for (const VertexH w : region)
    if (batchMark_[w.idx()] == batchStamp_) return true;
  for (const VertexH w : region) batchMark_[w.idx()] = batchStamp_;
  return false;
}

std::span<const Candidate> WeldBatcher::take(std::size_t most) {
  popped_.clear();
  while (popped_.size() < most && !heap_.empty()) popped_.push_back(heap_.pop());
  poppedRanked_.resize(popped_.size());
  forEach(popped_.size(), true, [&](std::size_t i) {
    fetchAhead(mesh_, i, popped_.size(), [&](std::size_t j) { return VertexH(int(popped_[j].vertex)); });
    auto& [c, valid, region] = poppedRanked_[i];
    c = popped_[i];
    valid = c.ranked || ranker_.evaluate(VertexH(int(c.vertex)), c, scratch_.local());
    if (valid) weldRegion(VertexH(int(c.vertex)), VertexH(int(c.target)), region);
  });

  ++batchStamp_;
  taken_.clear();
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
    taken_.push_back(c);
  }
  return taken_;
}

}  // namespace isoatlas::multires::simplify
