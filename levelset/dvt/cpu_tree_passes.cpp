#include "levelset/dvt/cpu_tree_passes.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_scan.h>

#include <array>
#include <atomic>
#include <numeric>

namespace isoatlas::levelset::dvt {
namespace {

constexpr std::size_t kGrain = 4096;
constexpr std::uint32_t kNoHit = 0xffffffffu;

// An expanded leaf's new nodes, and its voxels [begin, end) in the input.
struct Expansion {
  std::uint32_t size = 0, begin = 0, end = 0;
};

class CpuTreePasses final : public TreePasses {
public:
  std::string name() const override { return "cpu"; }

  void load(const VolumeTree& tree) override {
    frame_ = tree.frame;
    scales_ = childScales(frame_);
    pointers_ = tree.pointers;
    cells_ = tree.cells;
    marks_.assign(pointers_.size(), kMarkNone);
    removals_.assign(pointers_.size() + 1, 0);
  }

  VolumeTree download() const override {
    VolumeTree t;
    t.frame = frame_;
    t.pointers = pointers_;
    t.cells = cells_;
    return t;
  }

  std::uint64_t nodeCount() const override { return pointers_.size(); }

  std::uint64_t bytes() const override {
    return pointers_.capacity() * sizeof(Pointer) + cells_.capacity() * 4 + marks_.capacity() * 4 +
           remap_.capacity() * 4 + removals_.capacity() * 4 + input_.capacity() * sizeof(InputVoxel);
  }

  void setInput(const std::vector<InputVoxel>& input) override {
    input_ = input;
    hits_.resize(input_.size());
  }

  std::uint64_t mark(Op op) override {
    op_ = op;
    clearMarks();
    expansions_.resize(pointers_.size());  // only the expanded leaves' are used, cleared as marked
    const std::uint64_t marks = sum(input_.size(), [&](std::size_t i) { return markFor(i, op); });
    // The reduced subtrees: +1 at their root and -1 at their last node, summed before each node: > 0
    // for the nodes below a reduced root (removed whole by the next restructure).
    if (reduced_) std::exclusive_scan(removals_.begin(), removals_.end(), removals_.begin(), std::int32_t(0));
    return marks;
  }

  std::uint64_t markCollapse() override {
    clearMarks();
    std::fill(hits_.begin(), hits_.end(), kNoHit);  // no voxel expands anything in a collapse
    return sum(pointers_.size(), [&](std::size_t n) -> std::uint64_t {
      const Pointer& p = pointers_[n];
      if (p.leaf() || !collapsible(pointers_[std::size_t(p.left)], pointers_[std::size_t(p.right)])) return 0;
      marks_[n] = kMarkCollapse;
      return 1;
    });
  }

  Plan plan(bool allowExpand) override {
    const std::size_t count = pointers_.size();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, input_.size(), kGrain), [&](const auto& r) {
      for (std::size_t i = r.begin(); i < r.end(); ++i) planInput(i);
    });
    // Each node's count, prefix-summed in the same pass (TBB's scan runs the body twice over a range
    // when it must: first to sum, then to write).
    remap_.resize(count + 1);
    struct Sums {
      std::uint32_t nodes = 0;
      std::uint64_t changes = 0;
    };
    const Sums total = tbb::parallel_scan(
        tbb::blocked_range<std::size_t>(0, count, kGrain), Sums{},
        [&](const tbb::blocked_range<std::size_t>& r, Sums s, bool final) {
          for (std::size_t n = r.begin(); n < r.end(); ++n) {
            const auto [emit, change] = emitOf(n, allowExpand);
            if (final) remap_[n] = s.nodes;
            s.nodes += emit, s.changes += change;
          }
          return s;
        },
        [](const Sums& a, const Sums& b) { return Sums{a.nodes + b.nodes, a.changes + b.changes}; });
    remap_[count] = total.nodes;
    return {total.nodes, total.changes};
  }

  void restructure(const Plan& plan, bool allowExpand, std::uint64_t) override {
    // Into the spare streams (kept between writes, so no allocation or clearing per pass).
    spare_.resize(plan.nodes);
    spareCells_.resize(2 * plan.nodes);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pointers_.size(), kGrain), [&](const auto& r) {
      for (std::size_t n = r.begin(); n < r.end(); ++n) writeNode(n, allowExpand);
    });
    std::swap(pointers_, spare_);
    std::swap(cells_, spareCells_);
    marks_.resize(pointers_.size());
    removals_.resize(pointers_.size() + 1);
  }

private:
  template <class F>
  static std::uint64_t sum(std::size_t count, const F& f) {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, count, kGrain), std::uint64_t(0),
        [&](const auto& r, std::uint64_t s) {
          for (std::size_t i = r.begin(); i < r.end(); ++i) s += f(i);
          return s;
        },
        std::plus<>());
  }

  void clearMarks() {
    std::fill(marks_.begin(), marks_.end(), std::uint32_t(kMarkNone));
    if (reduced_) std::fill(removals_.begin(), removals_.end(), 0);
    reduced_ = false;
  }
  void setMark(std::size_t n, Mark m) { std::atomic_ref<std::uint32_t>(marks_[n]).store(m, std::memory_order_relaxed); }
  Mark markOf(std::size_t n) const { return Mark(marks_[n]); }

  Cell inputCell(std::size_t i) const { return unpackCell(input_[i].xy, input_[i].zd); }

  // The mark pass for one input voxel (dvt_mark.comp).
  std::uint64_t markFor(std::size_t i, Op op) {
    const InputVoxel& in = input_[i];
    const Cell c = unpackCell(in.xy, in.zd);
    hits_[i] = kNoHit;
    const float incoming = inputValue(op, in.value);
    std::size_t n = 0;
    for (std::uint32_t d = 0;; ++d) {
      Pointer& p = pointers_[n];
      if (p.leaf()) {
        if (d == c.depth) {
          const float v = combined(op, p.value, incoming);
          if (v != p.value) p.value = v;
          return 0;
        }
        if (saturated(op, p.value)) return 0;
        setMark(n, kMarkExpand);
        std::atomic_ref<std::uint32_t>(expansions_[n].size).store(0, std::memory_order_relaxed);  // planInput adds
        hits_[i] = std::uint32_t(n);
        return 1;
      }
      if (d == c.depth) {
        p.value = incoming;  // the value of the leaf it becomes (no other input voxel reaches n)
        setMark(n, kMarkReduce);
        std::atomic_ref<std::int32_t>(removals_[n]).fetch_add(1, std::memory_order_relaxed);
        std::atomic_ref<std::int32_t>(removals_[subtreeEnd(n) - 1]).fetch_sub(1, std::memory_order_relaxed);
        std::atomic_ref<bool>(reduced_).store(true, std::memory_order_relaxed);
        return 1;
      }
      n = std::size_t(childTowards(c, d) == 0 ? p.left : p.right);
    }
  }

  // The index just past n's subtree (tree_rules.glsl: subtreeEnd).
  std::size_t subtreeEnd(std::size_t n) const {
    for (std::size_t m = n; m != 0;) {
      const auto q = std::size_t(pointers_[m].parent);
      if (pointers_[q].left == std::int32_t(m)) return std::size_t(pointers_[q].right);
      m = q;
    }
    return pointers_.size();
  }

  // Per input voxel with a hit (dvt_runs.comp): the new nodes its leaf's subtree needs for it, two per
  // ancestor of the voxel below the leaf (down to the cut) that the previous voxel does not share; the
  // bounds of the leaf's run of voxels.
  void planInput(std::size_t i) {
    const std::uint32_t leaf = hits_[i];
    if (leaf == kNoHit) return;
    const Cell c = inputCell(i);
    const bool first = i == 0 || hits_[i - 1] != leaf, last = i + 1 == input_.size() || hits_[i + 1] != leaf;
    const std::uint32_t leafDepth = cells_[2 * leaf + 1] >> 16, cut = std::min(c.depth, expansionCut(op_, pointers_[leaf].value, leafDepth, kExpandLevels, scales_.data()));
    const std::uint32_t known = first ? leafDepth : std::min(commonDepth(inputCell(i - 1), c) + 1, cut);
    Expansion& e = expansions_[leaf];
    std::atomic_ref<std::uint32_t>(e.size).fetch_add(2 * (cut - known), std::memory_order_relaxed);
    if (first) e.begin = std::uint32_t(i);
    if (last) e.end = std::uint32_t(i + 1);
  }

  // How many nodes n becomes, and whether that changes the tree (dvt_plan.comp).
  std::pair<std::uint32_t, std::uint64_t> emitOf(std::size_t n, bool allowExpand) const {
    const Pointer& p = pointers_[n];
    if (removals_[n] > 0) return {0, 1};  // inside a reduced subtree
    if (p.parent >= 0 && markOf(std::size_t(p.parent)) == kMarkCollapse) return {0, 1};
    const Mark m = markOf(n);
    if (m == kMarkExpand) return allowExpand ? std::pair<std::uint32_t, std::uint64_t>{1 + expansions_[n].size, 1} : std::pair<std::uint32_t, std::uint64_t>{1, 0};
    return {1, m == kMarkReduce || m == kMarkCollapse ? 1 : 0};
  }

  // The restructure pass for one old node (dvt_restructure.comp).
  void writeNode(std::size_t n, bool allowExpand) {
    if (remap_[n + 1] == remap_[n]) return;  // removed
    const std::uint32_t o = remap_[n];
    const Pointer& p = pointers_[n];
    const Mark m = markOf(n);
    Pointer out;
    out.value = p.value;
    if (p.parent >= 0) out.parent = std::int32_t(remap_[std::size_t(p.parent)]);  // a kept node's parent is kept
    const bool expand = m == kMarkExpand && allowExpand;
    if (m == kMarkCollapse) out.value = pointers_[std::size_t(p.left)].value;
    spareCells_[2 * o] = cells_[2 * n], spareCells_[2 * o + 1] = cells_[2 * n + 1];
    if (expand) return generate(o, out, unpackCell(cells_[2 * n], cells_[2 * n + 1]), expansions_[n]);
    if (!p.leaf() && m != kMarkReduce && m != kMarkCollapse)
      out.left = std::int32_t(remap_[std::size_t(p.left)]), out.right = std::int32_t(remap_[std::size_t(p.right)]);
    spare_[o] = out;
  }

  // The first voxel of [a, b) (all inside `cell`, in pre-order) in the cell's upper half.
  std::uint32_t splitOf(const Cell& cell, std::uint32_t a, std::uint32_t b) const {
    while (a < b) {
      const std::uint32_t m = a + (b - a) / 2;
      if (childTowards(inputCell(m), cell.depth) == 0) a = m + 1;
      else b = m;
    }
    return a;
  }

  // The subtree an expanded leaf at new index o grows (dvt_restructure.comp: generate): depth first,
  // each node split where voxels lie strictly inside it, new nodes in pre-order after o; values from
  // the leaf's, one child scale per level (as splitting a level at a time would give); nodes at the
  // cut (expansionCut) stay leaves. A node's record is written whole when its children are
  // known, as the GLSL twin must.
  void generate(std::uint32_t o, const Pointer& leaf, const Cell& root, const Expansion& e) {
    std::array<float, kMaxDepth + 2> chain{};
    chain[root.depth] = leaf.value;
    for (std::uint32_t d = root.depth; d <= std::uint32_t(kMaxDepth); ++d) chain[d + 1] = childValue(chain[d], scales_[d]);
    struct Frame {
      Pointer pointer;
      Cell cell;
      std::uint32_t node, begin, split, end;
      int next;  // the child to make next; 2: done
    };
    std::array<Frame, kExpandLevels + 1> stack;
    const std::uint32_t cut = expansionCut(op_, leaf.value, root.depth, kExpandLevels, scales_.data());
    int top = 0;
    stack[0] = {leaf, root, o, e.begin, splitOf(root, e.begin, e.end), e.end, 0};
    std::uint32_t at = o + 1;
    while (top >= 0) {
      Frame& f = stack[std::size_t(top)];
      if (f.next == 2) {
        spare_[f.node] = f.pointer;
        --top;
        continue;
      }
      const int k = f.next++;
      const Cell child = childCell(f.cell, k);
      const std::uint32_t a = k == 0 ? f.begin : f.split, b = k == 0 ? f.split : f.end;
      const std::uint32_t q = at++;
      (k == 0 ? f.pointer.left : f.pointer.right) = std::int32_t(q);
      const Pointer p{std::int32_t(f.node), kNone, kNone, chain[child.depth]};
      const auto packed = packCell(child);
      spareCells_[2 * q] = packed[0], spareCells_[2 * q + 1] = packed[1];
      if (a < b && child.depth < cut && !(b - a == 1 && inputCell(a) == child)) {
        stack[std::size_t(++top)] = {p, child, q, a, splitOf(child, a, b), b, 0};
      } else {
        spare_[q] = p;
      }
    }
  }

  TreeFrame frame_;
  std::vector<float> scales_;
  std::vector<Pointer> pointers_, spare_;
  std::vector<std::uint32_t> cells_, spareCells_, marks_, remap_;
  std::vector<std::int32_t> removals_;  // ranges of reduced subtrees (plan)
  bool reduced_ = false;
  Op op_ = Op::Union;                  // the write's (the expansions' cut)               // a reduce mark was set since the marks were cleared
  std::vector<InputVoxel> input_;
  std::vector<std::uint32_t> hits_;       // per input voxel: the leaf it expands, or kNoHit
  std::vector<Expansion> expansions_;     // per node: its expansion's size and voxels (plan)
};

}  // namespace

std::unique_ptr<TreePasses> makeCpuTreePasses() { return std::make_unique<CpuTreePasses>(); }

}  // namespace isoatlas::levelset::dvt
