// The CPU tree's bricks (cpu_tree_passes.cpp): the subtrees below the brick depth, each a pre-order
// stream of its own, written by the paper's passes (mark, plan by a prefix sum, restructure through
// the remap stream) as the GPU writes its one stream; and what the bricks' passes and the top's share
// (the write's context, the walk down from the previous voxel, an expansion's new nodes).
#pragma once
#include <algorithm>
#include <cstdint>
#include <mutex>
#include <numeric>
#include <vector>

#include "edit/dvt/tree_rules.h"
#include "edit/dvt/volume_tree.h"

namespace isoatlas::edit::dvt::cpu {

inline constexpr std::uint32_t kNoHit = 0xffffffffu;
inline constexpr std::int32_t kInTop = -1;  // a voxel's route when the tree above the bricks took it

// The depth the CPU cuts the tree at: bricks of 16^3 voxels (a few thousand nodes where the surface is).
inline std::uint32_t brickDepthOf(const TreeFrame& frame) { return 3 * std::uint32_t(std::max(1, frame.voxelSplits - 4)); }

// An expanded leaf's new nodes, its voxels [begin, end) in the input, its cut (expansionCut) and
// its depth.
struct Expansion {
  std::uint32_t size = 0, begin = 0, end = 0, cut = 0, depth = 0;
};

// The new nodes an expansion makes for voxel `c` of a leaf at leafDepth cut at `cut`: two per depth on
// its path below the leaf, down to the cut, that the previous voxel of the same leaf does not share.
inline std::uint32_t newNodesFor(const Cell* previous, const Cell& c, std::uint32_t leafDepth, std::uint32_t cut) {
  cut = std::min(cut, c.depth);
  const std::uint32_t known = previous ? std::min(commonDepth(*previous, c) + 1, cut) : leafDepth;
  return 2 * (cut - known);
}

// The first voxel of [a, b) (all inside `cell`, in pre-order) in the cell's upper half.
inline std::uint32_t splitOf(const std::vector<InputVoxel>& input, const Cell& cell, std::uint32_t a, std::uint32_t b) {
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
inline float uniformValue(float value) { return value == kInside || value == kOutside ? value : 0; }

// How a node an expansion makes ends: split on where voxels lie strictly inside it above the cut;
// a voxel's own cell takes the voxel's value at once (the value the next mark would write).
inline bool splitsOn(const WriteContext& w, const Cell& node, std::uint32_t a, std::uint32_t b, std::uint32_t cut) {
  return a < b && node.depth < cut && !(b - a == 1 && w.inputCell(a) == node);
}
inline float newLeafValue(const WriteContext& w, const Cell& node, std::uint32_t a, std::uint32_t b, float value) {
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

}  // namespace isoatlas::edit::dvt::cpu
