#include "levelset/dvt/cpu_tree_passes.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <mutex>
#include <numeric>

namespace isoatlas::levelset::dvt {
namespace {

constexpr std::uint32_t kNoHit = 0xffffffffu;
constexpr std::int32_t kInTop = -1;  // a voxel's route when the tree above the bricks took it

// The depth the CPU cuts the tree at: bricks of 16^3 voxels (a few thousand nodes where the surface is).
std::uint32_t brickDepthOf(const TreeFrame& frame) { return 3 * std::uint32_t(std::max(1, frame.voxelSplits - 4)); }

// An expanded leaf's new nodes, its voxels [begin, end) in the input, its cut (expansionCut) and
// its depth.
struct Expansion {
  std::uint32_t size = 0, begin = 0, end = 0, cut = 0, depth = 0;
};

// The new nodes an expansion makes for voxel `c` of a leaf at leafDepth cut at `cut`: two per depth on
// its path below the leaf, down to the cut, that the previous voxel of the same leaf does not share.
std::uint32_t newNodesFor(const Cell* previous, const Cell& c, std::uint32_t leafDepth, std::uint32_t cut) {
  cut = std::min(cut, c.depth);
  const std::uint32_t known = previous ? std::min(commonDepth(*previous, c) + 1, cut) : leafDepth;
  return 2 * (cut - known);
}

// The first voxel of [a, b) (all inside `cell`, in pre-order) in the cell's upper half.
std::uint32_t splitOf(const std::vector<InputVoxel>& input, const Cell& cell, std::uint32_t a, std::uint32_t b) {
  while (a < b) {
    const std::uint32_t m = a + (b - a) / 2;
    if (childTowards(unpackCell(input[m].xy, input[m].zd), cell.depth) == 0) a = m + 1;
    else b = m;
  }
  return a;
}

// Where a walk down the tree may start: voxels come in pre-order, so most share a long path from the
// root with the voxel before, whose walk is remembered here (node by depth).
template <class Index>
struct Walk {
  std::array<Index, kMaxDepth + 1> nodes{};
  std::uint32_t last = 0;  // the depth the last walk ended at
  Cell previous;
  bool started = false;
  // The depth to go on from, with its node in `node`.
  std::uint32_t resume(const Cell& c, std::uint32_t rootDepth, Index root, Index& node) const {
    if (!started) return node = root, rootDepth;
    const std::uint32_t d = std::min(commonDepth(previous, c), last);
    return node = nodes[d], d;
  }
  void ended(const Cell& c, std::uint32_t depth) { previous = c, last = depth, started = true; }
};

// What one brick's passes share: the input, the write's op, the child scales.
struct WriteContext {
  const std::vector<InputVoxel>& input;
  const std::vector<float>& scales;
  Op op;
  Cell inputCell(std::size_t i) const { return unpackCell(input[i].xy, input[i].zd); }
};

// A leaf value a subtree can collapse to (kInside or kOutside), else 0.
float uniformValue(float value) { return value == kInside || value == kOutside ? value : 0; }

// How a node an expansion makes ends: split on where voxels lie strictly inside it above the cut;
// a voxel's own cell takes the voxel's value at once (the value the next mark would write).
bool splitsOn(const WriteContext& w, const Cell& node, std::uint32_t a, std::uint32_t b, std::uint32_t cut) {
  return a < b && node.depth < cut && !(b - a == 1 && w.inputCell(a) == node);
}
float newLeafValue(const WriteContext& w, const Cell& node, std::uint32_t a, std::uint32_t b, float value) {
  return b - a == 1 && w.inputCell(a) == node ? combined(w.op, value, inputValue(w.op, w.input[a].value)) : value;
}

// A brick's state during a write's passes, lent from a pool so their storage is reused.
struct PassState {
  std::vector<std::uint8_t> marks;  // Mark
  std::vector<std::uint32_t> remap;
  std::vector<std::int32_t> removals;  // ranges of reduced subtrees (plan), when some are
  std::vector<std::uint32_t> expanded;  // the expanded leaves in pre-order, and their expansions
  std::vector<Expansion> expansions;
  std::uint64_t bytes() const {
    return marks.capacity() + (remap.capacity() + removals.capacity() + expanded.capacity()) * 4 + expansions.capacity() * sizeof(Expansion);
  }
};
class PassStatePool {
public:
  PassState take() {
    const std::lock_guard lock(mutex_);
    if (spare_.empty()) return {};
    PassState s = std::move(spare_.back());
    spare_.pop_back();
    return s;
  }
  void give(PassState&& s) {
    const std::lock_guard lock(mutex_);
    spare_.push_back(std::move(s));
  }
  std::uint64_t bytes() const {
    std::uint64_t b = 0;
    for (const PassState& s : spare_) b += s.bytes();
    return b;
  }

private:
  std::mutex mutex_;
  std::vector<PassState> spare_;
};

// A node of a brick: in pre-order an inner node's left child is the next node, so only the right
// child is kept (kNone: a leaf); parents and cells follow from the path down (8 bytes a node where the
// one stream's Pointer and cell take 24).
struct BrickNode {
  std::int32_t right = kNone;
  float value = kOutside;
  bool leaf() const { return right < 0; }
};

// A brick: the subtree under one cell of the brick depth as its own pre-order stream of BrickNodes
// (root at index 0), written by the paper's passes (mark, plan by a prefix sum, restructure through
// the remap stream) as the GPU writes its one stream. The pass state lives only while the brick has
// marks.
struct Brick {
  std::vector<BrickNode> nodes;
  Cell root;  // its root's cell
  PassState pass;
  bool marked = false;
  std::uint32_t begin = 0, end = 0;    // its voxels in the input
  std::uint32_t planned = 0;           // nodes after the plan
  bool reduced = false;
  bool dirty = true;  // changed since a collapse last found nothing in it

  std::size_t size() const { return nodes.size(); }
  // The depth of node n, an ancestor of cell c (or c's own), found on the way down to c.
  std::uint32_t depthOf(std::size_t n, const Cell& c) const {
    std::uint32_t d = root.depth;
    for (std::size_t m = 0; m != n; ++d) m = childTowards(c, d) == 0 ? m + 1 : std::size_t(nodes[m].right);
    return d;
  }

  void startMarks(PassStatePool& pool) {
    pass = pool.take();
    pass.marks.assign(size(), kMarkNone);
    reduced = false, marked = true;
  }
  void endPass(PassStatePool& pool) {
    if (marked) pool.give(std::move(pass));
    pass = {}, marked = false;
    begin = end = 0;
  }

  // The index just past n's subtree: past the last leaf down its right children.
  std::size_t subtreeEnd(std::size_t n) const {
    while (!nodes[n].leaf()) n = std::size_t(nodes[n].right);
    return n + 1;
  }

  // The mark pass for the brick's voxels; reduced subtrees' ranges summed before each node (> 0 below
  // a reduced node: the plan removes those whole).
  std::uint64_t markRun(const WriteContext& w, std::uint32_t rootDepth, std::vector<std::uint32_t>& hits, PassStatePool& pool) {
    std::uint64_t count = 0;
    Walk<std::uint32_t> walk;
    for (std::uint32_t i = begin; i < end; ++i) count += markFor(w, i, rootDepth, hits, walk, pool);
    if (reduced) std::exclusive_scan(pass.removals.begin(), pass.removals.end(), pass.removals.begin(), std::int32_t(0));
    return count;
  }

  // The mark pass for one input voxel below the brick's root (dvt_mark.comp, from the root down).
  std::uint64_t markFor(const WriteContext& w, std::size_t i, std::uint32_t rootDepth, std::vector<std::uint32_t>& hits,
                        Walk<std::uint32_t>& walk, PassStatePool& pool) {
    const InputVoxel& in = w.input[i];
    const Cell c = unpackCell(in.xy, in.zd);
    hits[i] = kNoHit;
    const float incoming = inputValue(w.op, in.value);
    std::uint32_t n = 0;
    for (std::uint32_t d = walk.resume(c, rootDepth, 0, n);; ++d) {
      walk.nodes[d] = n;
      walk.ended(c, d);
      BrickNode& p = nodes[n];
      if (p.leaf()) {
        if (d == c.depth) {
          const float v = combined(w.op, p.value, incoming);
          if (v != p.value) p.value = v, dirty = true;
          return 0;
        }
        if (saturated(w.op, p.value)) return 0;
        if (!marked) startMarks(pool);
        pass.marks[n] = kMarkExpand;
        hits[i] = n;
        return 1;
      }
      if (d == c.depth) {
        p.value = incoming;  // the value of the leaf it becomes
        if (!marked) startMarks(pool);
        pass.marks[n] = kMarkReduce;
        if (!reduced) pass.removals.assign(size() + 1, 0);
        ++pass.removals[n], --pass.removals[subtreeEnd(n) - 1];
        reduced = true;
        return 1;
      }
      n = childTowards(c, d) == 0 ? n + 1 : std::uint32_t(p.right);
    }
  }

  // Marks the roots of the largest subtrees whose leaves all hold one uniform value, each to become a
  // leaf of that value with its subtree removed (as a reduction): the whole of what collapsing a level
  // a pass ends with.
  std::uint64_t markCollapse(PassStatePool& pool) {
    begin = end = 0;  // no voxels (those of the last write are gone)
    static thread_local std::vector<float> uniform;  // per node: its subtree's one value, or 0
    uniform.resize(size());
    for (std::size_t n = size(); n-- > 0;) {
      const BrickNode& p = nodes[n];
      uniform[n] = p.leaf() ? uniformValue(p.value) : (uniform[n + 1] == uniform[std::size_t(p.right)] ? uniform[n + 1] : 0);
    }
    std::uint64_t count = 0;
    for (std::size_t n = 0; n < size();) {
      if (nodes[n].leaf() || uniform[n] == 0) {
        ++n;
        continue;
      }
      if (count++ == 0) startMarks(pool);
      pass.marks[n] = kMarkCollapse;
      nodes[n].value = uniform[n];  // the value of the leaf it becomes
      const std::size_t next = subtreeEnd(n);
      if (!reduced) pass.removals.assign(size() + 1, 0), reduced = true;
      ++pass.removals[n], --pass.removals[next - 1];
      n = next;
    }
    if (reduced) std::exclusive_scan(pass.removals.begin(), pass.removals.end(), pass.removals.begin(), std::int32_t(0));
    dirty = false;  // these marks are all it has to collapse
    return count;
  }

  // The plan: expansion sizes from the voxels that hit leaves, then each node's count prefix-summed
  // into the remap stream (dvt_runs.comp, dvt_plan.comp). Returns the changes.
  std::uint64_t plan(const WriteContext& w, const std::vector<std::uint32_t>& hits, bool allowExpand) {
    pass.expanded.clear(), pass.expansions.clear();  // the plan may run twice (the node budget)
    for (std::uint32_t i = begin; i < end; ++i) {
      const std::uint32_t leaf = hits[i];
      if (leaf == kNoHit) continue;
      const bool first = i == begin || hits[i - 1] != leaf;
      if (first) {
        const std::uint32_t depth = depthOf(leaf, w.inputCell(i));
        pass.expanded.push_back(leaf);
        pass.expansions.push_back({0, i, i, expansionCut(w.op, nodes[leaf].value, depth, kMaxDepth, w.scales.data()), depth});
      }
      Expansion& e = pass.expansions.back();
      const Cell c = w.inputCell(i), previous = first ? c : w.inputCell(i - 1);
      e.size += newNodesFor(first ? nullptr : &previous, c, e.depth, e.cut);
      e.end = i + 1;
    }
    pass.remap.resize(size() + 1);
    std::uint32_t nodes = 0;
    std::uint64_t changes = 0;
    std::size_t expansion = 0;  // the next expanded leaf's (they come in pre-order)
    for (std::size_t n = 0; n < size(); ++n) {
      pass.remap[n] = nodes;
      const Mark m = Mark(pass.marks[n]);
      const std::uint32_t grows = m == kMarkExpand ? pass.expansions[expansion++].size : 0;
      if (reduced && pass.removals[n] > 0) {
        ++changes;  // inside a reduced or collapsed subtree
        continue;
      }
      nodes += 1 + (allowExpand ? grows : 0);
      changes += (m == kMarkExpand && allowExpand) || m == kMarkReduce || m == kMarkCollapse;
    }
    pass.remap[size()] = planned = nodes;
    return changes;
  }

  // The restructure pass: every kept node to its new index, pointers remapped, expanded leaves
  // followed by their new subtrees (dvt_restructure.comp).
  void restructure(const WriteContext& w, bool allowExpand, PassStatePool& pool) {
    std::vector<BrickNode> newNodes(planned);
    std::size_t expansion = 0;
    for (std::size_t n = 0; n < size(); ++n) {
      const Mark m = Mark(pass.marks[n]);
      const Expansion* e = m == kMarkExpand ? &pass.expansions[expansion++] : nullptr;
      if (pass.remap[n + 1] == pass.remap[n]) continue;  // removed
      const std::uint32_t o = pass.remap[n];
      const BrickNode& p = nodes[n];
      if (e && allowExpand) {
        generate(w, o, p.value, *e, newNodes.data());
        continue;
      }
      const bool staysInner = !p.leaf() && m != kMarkReduce && m != kMarkCollapse;
      newNodes[o] = {staysInner ? std::int32_t(pass.remap[std::size_t(p.right)]) : kNone, p.value};
    }
    nodes = std::move(newNodes);
    if (begin < end) dirty = true;  // a write's (a collapse's leaves nothing to collapse)
    endPass(pool);
  }

  // The subtree an expanded leaf at new index o grows, written in pre-order after o in one pass over
  // its voxels (a trie of their paths): a node above the cut (expansionCut: here no level limit) that
  // strictly holds a voxel splits; the other new nodes are leaves, a voxel's own cell with its value
  // (newLeafValue), the rest with the leaf's value carried down one child scale a level. Voxels come
  // in pre-order, so each leaves the previous one's path where its right sibling is still to be made.
  static void generate(const WriteContext& w, std::uint32_t o, float leafValue, const Expansion& e, BrickNode* newNodes) {
    std::array<float, kMaxDepth + 2> chain{};
    chain[e.depth] = leafValue;
    for (std::uint32_t d = e.depth; d <= std::uint32_t(kMaxDepth); ++d) chain[d + 1] = childValue(chain[d], w.scales[d]);
    std::array<std::uint32_t, kMaxDepth + 1> node{};  // the current path's node at each depth
    std::uint64_t rightToMake = 0;  // bit d: the path's node at depth d has its left child only
    std::uint32_t at = o + 1, last = e.depth;
    node[e.depth] = o;
    newNodes[o] = {kNone, leafValue};
    // The child k of the path's node at depth d, made at the next index (a left child comes right
    // after its parent: pre-order).
    const auto make = [&](std::uint32_t d, int k, float value) {
      const std::uint32_t q = at++;
      if (k == 1) newNodes[node[d]].right = std::int32_t(q);
      newNodes[q] = {kNone, value};
      return q;
    };
    const auto makeRightLeaves = [&](std::uint32_t above) {  // the siblings still to make, deepest first
      for (std::uint32_t d = last; d-- > above;)
        if (rightToMake >> d & 1u) make(d, 1, chain[d + 1]), rightToMake &= ~(std::uint64_t(1) << d);
    };
    for (std::uint32_t i = e.begin; i < e.end; ++i) {
      const Cell c = w.inputCell(i);
      const std::uint32_t end = std::min(e.cut, c.depth);  // the depth its path ends at
      std::uint32_t d = e.depth;
      if (i != e.begin) {
        const std::uint32_t common = commonDepth(w.inputCell(i - 1), c);
        if (common >= e.cut) continue;  // in the previous voxel's leaf at the cut
        makeRightLeaves(common + 1);
        rightToMake &= ~(std::uint64_t(1) << common);
        node[common + 1] = make(common, 1, chain[common + 1]);
        d = common + 1;
      }
      for (; d < end; ++d) {
        const int k = childTowards(c, d);
        if (k == 1) make(d, 0, chain[d + 1]);
        else rightToMake |= std::uint64_t(1) << d;
        node[d + 1] = make(d, k, chain[d + 1]);
      }
      if (end == c.depth) newNodes[node[end]].value = combined(w.op, chain[end], inputValue(w.op, w.input[i].value));
      last = end;
    }
    makeRightLeaves(e.depth);
  }

  // A new one-leaf brick grown at once for its voxels [a, b) (a top leaf's expansion going on into it).
  void growNew(const WriteContext& w, std::uint32_t a, std::uint32_t b) {
    const std::uint32_t cut = expansionCut(w.op, nodes[0].value, root.depth, kMaxDepth, w.scales.data());
    Expansion e{0, a, b, cut, root.depth};
    for (std::uint32_t i = a; i < b; ++i) {
      const Cell previous = w.inputCell(i == a ? i : i - 1);
      e.size += newNodesFor(i == a ? nullptr : &previous, w.inputCell(i), root.depth, cut);
    }
    std::vector<BrickNode> newNodes(1 + e.size);
    generate(w, 0, nodes[0].value, e, newNodes.data());
    nodes = std::move(newNodes);
  }
};

// The tree above the bricks: a small index of nodes allocated in pairs of siblings (children: the
// first of the pair; at the depth above the bricks, the first of a pair of bricks).
struct TopNode {
  std::uint32_t xy = 0, zd = 0;
  float value = kOutside;
  std::int32_t children = kNone;
  std::uint32_t mark = kMarkNone;
  Expansion expansion;
  Cell cell() const { return unpackCell(xy, zd); }
  bool leaf() const { return children < 0; }
};

// Slots allocated in pairs, freed pairs reused.
template <class T>
struct PairPool {
  std::vector<T> items;
  std::vector<std::int32_t> freePairs;
  std::int32_t allocate() {
    if (!freePairs.empty()) {
      const std::int32_t p = freePairs.back();
      freePairs.pop_back();
      return p;
    }
    items.resize(items.size() + 2);
    return std::int32_t(items.size() - 2);
  }
  void release(std::int32_t pair) {
    items[std::size_t(pair)] = T{}, items[std::size_t(pair) + 1] = T{};
    freePairs.push_back(pair);
  }
};

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
    loadTop(tree, 0, tree.nodeCount(), 0);
  }

  VolumeTree download() const override {
    VolumeTree t;
    t.frame = frame_;
    t.pointers.reserve(nodeCount());
    t.cells.reserve(2 * nodeCount());
    emitTop(t, 0, kNone);
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

  // The stream's subtree [n, end) at depth `depth` into top node t.
  void loadTop(const VolumeTree& tree, std::size_t n, std::size_t end, std::int32_t t) {
    const Pointer& p = tree.pointers[n];
    ++topNodes_;
    {
      TopNode& node = top_.items[std::size_t(t)];
      node.xy = tree.cells[2 * n], node.zd = tree.cells[2 * n + 1], node.value = p.value;
    }
    if (p.leaf()) return;
    const std::uint32_t depth = tree.cell(n).depth;
    const auto left = std::size_t(p.left), right = std::size_t(p.right);
    if (depth + 1 == brickDepth_) {
      const std::int32_t pair = bricks_.allocate();
      loadBrick(tree, left, right, bricks_.items[std::size_t(pair)]);
      loadBrick(tree, right, end, bricks_.items[std::size_t(pair) + 1]);
      top_.items[std::size_t(t)].children = pair;
      return;
    }
    const std::int32_t pair = top_.allocate();
    top_.items[std::size_t(t)].children = pair;
    loadTop(tree, left, right, pair);
    loadTop(tree, right, end, pair + 1);
  }

  void loadBrick(const VolumeTree& tree, std::size_t begin, std::size_t end, Brick& brick) {
    brick.nodes.resize(end - begin);
    for (std::size_t n = begin; n < end; ++n) {
      const Pointer& p = tree.pointers[n];
      brick.nodes[n - begin] = {p.leaf() ? kNone : p.right - std::int32_t(begin), p.value};
    }
    brick.root = tree.cell(begin);
    brickNodes_ += brick.size();
  }

  // Top node t and its subtree appended to the stream in pre-order; returns t's index there.
  std::int32_t emitTop(VolumeTree& out, std::int32_t t, std::int32_t parent) const {
    const TopNode& n = top_.items[std::size_t(t)];
    const auto o = std::int32_t(out.pointers.size());
    out.pointers.push_back({parent, kNone, kNone, n.value});
    out.cells.push_back(n.xy), out.cells.push_back(n.zd);
    if (n.leaf()) return o;
    std::int32_t left = 0, right = 0;
    if (n.cell().depth + 1 == brickDepth_) {
      left = emitBrick(out, bricks_.items[std::size_t(n.children)], o);
      right = emitBrick(out, bricks_.items[std::size_t(n.children) + 1], o);
    } else {
      left = emitTop(out, n.children, o);
      right = emitTop(out, n.children + 1, o);
    }
    out.pointers[std::size_t(o)].left = left, out.pointers[std::size_t(o)].right = right;
    return o;
  }

  static std::int32_t emitBrick(VolumeTree& out, const Brick& b, std::int32_t parent) {
    // Parents and cells down from the root's: children come after their parents in pre-order.
    const auto base = std::int32_t(out.pointers.size());
    out.pointers.resize(out.pointers.size() + b.size());
    out.cells.resize(out.cells.size() + 2 * b.size());
    Pointer* pointers = out.pointers.data() + base;
    std::uint32_t* cells = out.cells.data() + 2 * std::size_t(base);
    const auto root = packCell(b.root);
    cells[0] = root[0], cells[1] = root[1];
    pointers[0].parent = parent;
    for (std::size_t n = 0; n < b.size(); ++n) {
      const BrickNode& node = b.nodes[n];
      pointers[n].value = node.value;
      if (node.leaf()) continue;
      const std::size_t children[2] = {n + 1, std::size_t(node.right)};
      pointers[n].left = base + std::int32_t(children[0]), pointers[n].right = base + node.right;
      const Cell c = unpackCell(cells[2 * n], cells[2 * n + 1]);
      for (int k = 0; k < 2; ++k) {
        const auto child = packCell(childCell(c, k));
        cells[2 * children[k]] = child[0], cells[2 * children[k] + 1] = child[1];
        pointers[children[k]].parent = base + std::int32_t(n);
      }
    }
    return base;
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

}  // namespace isoatlas::levelset::dvt
