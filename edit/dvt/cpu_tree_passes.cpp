#include "edit/dvt/cpu_tree_passes.h"

#include "edit/dvt/cpu_brick.h"
#include "edit/dvt/cpu_tree_stream.h"
#include "edit/dvt/cpu_tree_top.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <mutex>
#include <numeric>

namespace isoatlas::edit::dvt {
namespace {

using namespace cpu;  // the bricks, the top and the stream's conversions: this file's parts

// The CPU passes. The paper's one pre-order stream makes every restructure move the whole tree (the
// price of absolute pointers), which a GPU's bandwidth pays easily and a CPU's does not; so the CPU
// cuts the stream at the brick depth: the tree above it is a small index of sibling pairs, each
// subtree below it a brick with streams of its own, and a write marks, plans and restructures only
// the bricks its voxels reach, in parallel. download() splices them back into the one stream, which
// equals the GPU's node for node.
class CpuTreePasses final : public TreePasses {
public:
  std::string name() const override { return "cpu"; }

  void load(const VolumeTree& tree) override {
    frame_ = tree.frame;
    scales_ = childScales(frame_);
    brickDepth_ = brickDepthOf(frame_);
    top_ = {}, bricks_ = {};
    topNodes_ = 0, brickNodes_ = 0;
    marked_.clear();
    top_.items.resize(1);  // the root
    loadStream(tree, brickDepth_, top_, bricks_, topNodes_, brickNodes_);
  }

  VolumeTree download() const override {
    VolumeTree t;
    t.frame = frame_;
    t.pointers.reserve(nodeCount());
    t.cells.reserve(2 * nodeCount());
    appendStream(t, brickDepth_, top_, bricks_);
    return t;
  }

  std::uint64_t nodeCount() const override { return topNodes_ + brickNodes_; }

  std::uint64_t bytes() const override {
    std::uint64_t b = top_.items.capacity() * sizeof(TopNode) + bricks_.items.capacity() * sizeof(Brick) +
                      input_.capacity() * sizeof(InputVoxel) + (hits_.capacity() + route_.capacity()) * 4;
    for (const Brick& k : bricks_.items)
      b += k.nodes.capacity() * sizeof(BrickNode) + k.pass.bytes();
    return b + states_.bytes();
  }

  void setInput(std::vector<InputVoxel> input) override {
    input_ = std::move(input);
    hits_.resize(input_.size());
    route_.resize(input_.size());
  }

  std::uint64_t mark(Op op) override {
    op_ = op;
    clearMarks();
    // Each voxel down the top to its brick (or to a top leaf or node it changes), in parallel. Voxels
    // in one brick's cell are consecutive and take the same way as the first of them.
    const WriteContext w = context();
    std::uint64_t marks = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, input_.size(), 1024), std::uint64_t(0),
        [&](const auto& r, std::uint64_t s) {
          Walk<std::int32_t> walk;
          Cell brickCell{0, 0, 0, kMaxDepth + 1};  // the previous voxel's cell at the brick depth
          for (std::size_t i = r.begin(); i < r.end(); ++i) {
            const Cell c = w.inputCell(i);
            const Cell previous = brickCell;
            brickCell = c.depth >= brickDepth_ ? ancestorAt(c, brickDepth_) : Cell{0, 0, 0, kMaxDepth + 1};
            if (brickCell.depth == brickDepth_ && brickCell == previous) {
              route_[i] = route_[i - 1], hits_[i] = hits_[i - 1];
              s += hits_[i] != kNoHit;
            } else {
              s += routeVoxel(w, i, walk);
            }
          }
          return s;
        },
        std::plus<>());
    // The voxels of a brick are consecutive (pre-order): each run marks its brick.
    std::vector<std::int32_t> reached;
    topHits_.clear();
    for (std::uint32_t i = 0; i < input_.size();) {
      std::uint32_t j = i + 1;
      if (route_[i] == kInTop && hits_[i] != kNoHit) topHits_.push_back(i);
      if (route_[i] != kInTop) {
        while (j < input_.size() && route_[j] == route_[i]) ++j;
        Brick& b = bricks_.items[std::size_t(route_[i])];
        b.begin = i, b.end = j;
        reached.push_back(route_[i]);
      }
      i = j;
    }
    marks += tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, reached.size(), 1), std::uint64_t(0),
        [&](const auto& r, std::uint64_t s) {
          for (std::size_t k = r.begin(); k < r.end(); ++k) s += bricks_.items[std::size_t(reached[k])].markRun(w, brickDepth_, hits_, states_);
          return s;
        },
        std::plus<>());
    for (const std::int32_t b : reached) {
      Brick& brick = bricks_.items[std::size_t(b)];
      if (brick.marked) marked_.push_back(b);
      else brick.begin = brick.end = 0;
    }
    return marks;
  }

  std::uint64_t markCollapse() override {
    clearMarks();
    input_.clear(), hits_.clear(), route_.clear(), topHits_.clear();  // no voxel expands anything in a collapse
    for (std::size_t b = 0; b < bricks_.items.size(); ++b)
      if (bricks_.items[b].dirty && !bricks_.items[b].nodes.empty()) dirtyBricks_.push_back(std::int32_t(b));
    std::uint64_t marks = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, dirtyBricks_.size(), 1), std::uint64_t(0),
        [&](const auto& r, std::uint64_t s) {
          for (std::size_t k = r.begin(); k < r.end(); ++k) {
            Brick& b = bricks_.items[std::size_t(dirtyBricks_[k])];
            s += b.markCollapse(states_);
          }
          return s;
        },
        std::plus<>());
    for (const std::int32_t b : dirtyBricks_)
      if (bricks_.items[std::size_t(b)].marked) marked_.push_back(b);
    dirtyBricks_.clear();
    markTopCollapsed(0, markTopCollapse(0, 0, marks), marks);
    return marks;
  }

  Plan plan(bool allowExpand) override {
    const WriteContext w = context();
    const std::uint64_t brickChanges = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, marked_.size(), 1), std::uint64_t(0),
        [&](const auto& r, std::uint64_t s) {
          for (std::size_t k = r.begin(); k < r.end(); ++k) s += bricks_.items[std::size_t(marked_[k])].plan(w, hits_, allowExpand);
          return s;
        },
        std::plus<>());
    std::int64_t delta = 0;
    for (const std::int32_t b : marked_) delta += std::int64_t(bricks_.items[std::size_t(b)].planned) - std::int64_t(bricks_.items[std::size_t(b)].size());
    std::uint64_t changes = brickChanges;
    planTop(allowExpand, delta, changes);
    return {std::uint64_t(std::int64_t(nodeCount()) + delta), changes};
  }

  void restructure(const Plan&, bool allowExpand, std::uint64_t) override {
    const WriteContext w = context();
    tbb::parallel_for(std::size_t(0), marked_.size(), [&](std::size_t k) {
      Brick& b = bricks_.items[std::size_t(marked_[k])];
      brickNodesDelta_.fetch_add(std::int64_t(b.planned) - std::int64_t(b.size()), std::memory_order_relaxed);
      b.restructure(w, allowExpand, states_);
    });
    brickNodes_ = std::uint64_t(std::int64_t(brickNodes_) + brickNodesDelta_.exchange(0));
    marked_.clear();
    // The top's marked nodes head disjoint subtrees (the voxels are disjoint; a collapsed node's
    // children are leaves), so each is applied alone.
    for (const std::int32_t t : topMarked_) restructureTop(w, t, allowExpand);
    for (const std::int32_t t : topMarked_) top_.items[std::size_t(t)].mark = kMarkNone;
    topMarked_.clear();
    // The bricks the top's expansions reached, grown in parallel.
    brickNodes_ += tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, newBricks_.size(), 1), std::uint64_t(0),
        [&](const auto& r, std::uint64_t s) {
          for (std::size_t k = r.begin(); k < r.end(); ++k) {
            Brick& b = bricks_.items[std::size_t(newBricks_[k].brick)];
            b.growNew(w, newBricks_[k].begin, newBricks_[k].end);
            s += b.size() - 1;
          }
          return s;
        },
        std::plus<>());
    newBricks_.clear();
  }

  bool restructureFinishesWrites() const override { return true; }

private:
  WriteContext context() const { return {input_, scales_, op_}; }

  void clearMarks() {
    for (const std::int32_t b : marked_) bricks_.items[std::size_t(b)].endPass(states_);
    marked_.clear();
    for (const std::int32_t t : topMarked_) top_.items[std::size_t(t)].mark = kMarkNone, top_.items[std::size_t(t)].expansion = {};
    topMarked_.clear();
  }

  void markTop(std::int32_t t, Mark m) {
    std::atomic_ref<std::uint32_t> mark(top_.items[std::size_t(t)].mark);
    if (mark.exchange(m, std::memory_order_relaxed) == kMarkNone) {
      const std::lock_guard lock(topMarkedMutex_);
      topMarked_.push_back(t);
    }
  }

  // Voxel i down the top: to its brick (route_), or to the top leaf or node it writes, expands or
  // reduces (the top's part of dvt_mark.comp). Returns the marks set.
  std::uint64_t routeVoxel(const WriteContext& w, std::size_t i, Walk<std::int32_t>& walk) {
    const InputVoxel& in = w.input[i];
    const Cell c = unpackCell(in.xy, in.zd);
    route_[i] = kInTop, hits_[i] = kNoHit;
    const float incoming = inputValue(w.op, in.value);
    std::int32_t t = 0;
    for (std::uint32_t d = walk.resume(c, 0, 0, t);; ++d) {
      walk.nodes[d] = t;
      walk.ended(c, d);
      TopNode& n = top_.items[std::size_t(t)];
      if (n.leaf()) {
        if (d == c.depth) {
          n.value = combined(w.op, n.value, incoming);
          return 0;
        }
        if (saturated(w.op, n.value)) return 0;
        markTop(t, kMarkExpand);
        hits_[i] = std::uint32_t(t);
        return 1;
      }
      if (d == c.depth) {
        n.value = incoming;
        markTop(t, kMarkReduce);
        return 1;
      }
      const std::int32_t child = n.children + childTowards(c, d);
      if (d + 1 == brickDepth_) {
        route_[i] = child;
        return 0;
      }
      t = child;
    }
  }

  // Marks the top's roots of the largest subtrees whose leaves (top leaves, or bricks that are one
  // leaf) all hold one uniform value, as Brick::markCollapse marks them; returns t's subtree's value
  // when it is one, else 0 (t itself is marked by the caller, who knows whether it is the largest).
  float markTopCollapse(std::int32_t t, std::uint32_t depth, std::uint64_t& marks) {
    const TopNode& n = top_.items[std::size_t(t)];
    if (n.leaf()) return uniformValue(n.value);
    float value[2];
    for (int k = 0; k < 2; ++k) {
      if (depth + 1 == brickDepth_) {
        const Brick& b = bricks_.items[std::size_t(n.children + k)];
        value[k] = b.size() == 1 ? uniformValue(b.nodes[0].value) : 0;
      } else {
        value[k] = markTopCollapse(n.children + k, depth + 1, marks);
      }
    }
    if (value[0] == value[1]) return value[0];
    // Not one value: its children with one are the largest such subtrees.
    for (int k = 0; k < 2 && depth + 1 < brickDepth_; ++k) markTopCollapsed(n.children + k, value[k], marks);
    return 0;
  }
  void markTopCollapsed(std::int32_t t, float value, std::uint64_t& marks) {
    TopNode& n = top_.items[std::size_t(t)];
    if (value == 0 || n.leaf()) return;
    n.value = value;  // the value of the leaf it becomes
    markTop(t, kMarkCollapse), ++marks;
  }

  // The top's marks in the plan: node count changes and changes.
  void planTop(bool allowExpand, std::int64_t& delta, std::uint64_t& changes) {
    for (const std::int32_t t : topMarked_) top_.items[std::size_t(t)].expansion = {};  // the plan may run twice
    for (const std::uint32_t i : topHits_) {  // the top leaves' expansions, from their voxels
      TopNode& leaf = top_.items[hits_[i]];
      const bool first = i == 0 || route_[i - 1] != kInTop || hits_[i - 1] != hits_[i];
      const Cell c = unpackCell(input_[i].xy, input_[i].zd), previous = first ? c : unpackCell(input_[i - 1].xy, input_[i - 1].zd);
      if (first) leaf.expansion.begin = std::uint32_t(i), leaf.expansion.cut = topCut(leaf);
      leaf.expansion.size += newNodesFor(first ? nullptr : &previous, c, leaf.cell().depth, leaf.expansion.cut);
      leaf.expansion.end = std::uint32_t(i + 1);
    }
    for (const std::int32_t t : topMarked_) {
      const TopNode& n = top_.items[std::size_t(t)];
      if (n.mark == kMarkExpand && allowExpand) delta += n.expansion.size, ++changes;
      if (n.mark == kMarkReduce || n.mark == kMarkCollapse) delta -= std::int64_t(subtreeNodes(t, n.cell().depth)) - 1, ++changes;
    }
  }

  std::uint32_t topCut(const TopNode& leaf) const { return expansionCut(op_, leaf.value, leaf.cell().depth, kMaxDepth, scales_.data()); }

  std::uint64_t subtreeNodes(std::int32_t t, std::uint32_t depth) const {
    const TopNode& n = top_.items[std::size_t(t)];
    if (n.leaf()) return 1;
    if (depth + 1 == brickDepth_) return 1 + bricks_.items[std::size_t(n.children)].size() + bricks_.items[std::size_t(n.children) + 1].size();
    return 1 + subtreeNodes(n.children, depth + 1) + subtreeNodes(n.children + 1, depth + 1);
  }

  // Applies a top node's mark.
  void restructureTop(const WriteContext& w, std::int32_t t, bool allowExpand) {
    const TopNode& n = top_.items[std::size_t(t)];
    const Mark m = Mark(n.mark);
    const std::uint32_t depth = n.cell().depth;
    if (m == kMarkExpand) {
      if (allowExpand) growTop(w, t, n.expansion.begin, n.expansion.end, n.expansion.cut);
      return;
    }
    releaseChildren(t, depth);  // its value is the leaf's it becomes (set when marked)
  }

  // Frees t's subtree below it (top pairs and bricks); t becomes a leaf.
  void releaseChildren(std::int32_t t, std::uint32_t depth) {
    const std::int32_t children = top_.items[std::size_t(t)].children;
    if (children < 0) return;
    if (depth + 1 == brickDepth_) {
      brickNodes_ -= bricks_.items[std::size_t(children)].size() + bricks_.items[std::size_t(children) + 1].size();
      bricks_.release(children);
    } else {
      releaseChildren(children, depth + 1), releaseChildren(children + 1, depth + 1);
      top_.release(children);
      topNodes_ -= 2;
    }
    top_.items[std::size_t(t)].children = kNone;
  }

  // An expanded top leaf's new subtree (as Brick::generate grows one): split where voxels lie strictly
  // inside, down to the cut; below the top, the children are new bricks, grown on after the top's marks
  // are applied (newBricks_).
  void growTop(const WriteContext& w, std::int32_t t, std::uint32_t a, std::uint32_t b, std::uint32_t cut) {
    const Cell cell = top_.items[std::size_t(t)].cell();
    const float value = childValue(top_.items[std::size_t(t)].value, scales_[cell.depth]);  // the children's
    const std::uint32_t split = splitOf(w.input, cell, a, b);
    const bool bricks = cell.depth + 1 == brickDepth_;
    const std::int32_t pair = bricks ? bricks_.allocate() : top_.allocate();
    top_.items[std::size_t(t)].children = pair;
    if (!bricks) topNodes_ += 2;
    for (int k = 0; k < 2; ++k) {
      const Cell child = childCell(cell, k);
      const std::uint32_t ca = k == 0 ? a : split, cb = k == 0 ? split : b;
      const bool splits = splitsOn(w, child, ca, cb, cut);
      const float v = splits ? value : newLeafValue(w, child, ca, cb, value);
      const auto packed = packCell(child);
      if (bricks) {
        Brick& brick = bricks_.items[std::size_t(pair + k)];
        brick.nodes = {BrickNode{kNone, v}};
        brick.root = child;
        brick.dirty = true;
        if (splits) newBricks_.push_back({pair + k, ca, cb});
        ++brickNodes_;
        continue;
      }
      TopNode& node = top_.items[std::size_t(pair + k)];
      node.xy = packed[0], node.zd = packed[1], node.value = v;
      if (splits) growTop(w, pair + k, ca, cb, cut);
    }
  }

  TreeFrame frame_;
  std::vector<float> scales_;
  std::uint32_t brickDepth_ = 3;
  Op op_ = Op::Union;
  PairPool<TopNode> top_;  // items[0]: the root
  PairPool<Brick> bricks_;
  PassStatePool states_;
  std::uint64_t topNodes_ = 0, brickNodes_ = 0;
  std::atomic<std::int64_t> brickNodesDelta_{0};
  std::vector<std::int32_t> marked_, dirtyBricks_;  // bricks with marks; bricks a collapse looks at
  std::vector<std::int32_t> topMarked_;            // top nodes with marks
  std::mutex topMarkedMutex_;
  std::vector<InputVoxel> input_;
  std::vector<std::uint32_t> hits_;  // per input voxel: the leaf it expands (top node or brick node), or kNoHit
  std::vector<std::int32_t> route_;  // per input voxel: its brick, or kInTop
  std::vector<std::uint32_t> topHits_;  // the voxels that expand top leaves
  struct NewBrick {
    std::int32_t brick;
    std::uint32_t begin, end;  // its voxels
  };
  std::vector<NewBrick> newBricks_;  // one-leaf bricks the top's expansions made, to grow for their voxels
};

}  // namespace

std::unique_ptr<TreePasses> makeCpuTreePasses() { return std::make_unique<CpuTreePasses>(); }

}  // namespace isoatlas::edit::dvt
