#include "levelset/dvt/cpu_tree_passes.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <atomic>
#include <numeric>

namespace isoatlas::levelset::dvt {
namespace {

constexpr std::size_t kGrain = 4096;

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

  void setInput(const std::vector<InputVoxel>& input) override { input_ = input; }

  std::uint64_t mark(Op op) override {
    clearMarks();
    const std::uint64_t marks = sum(input_.size(), [&](std::size_t i) { return markFor(input_[i], op); });
    // The reduced subtrees: +1 at their root and -1 at their last node, summed before each node: > 0
    // for the nodes below a reduced root (removed whole by the next restructure).
    if (reduced_) std::exclusive_scan(removals_.begin(), removals_.end(), removals_.begin(), std::int32_t(0));
    return marks;
  }

  std::uint64_t markCollapse() override {
    clearMarks();
    return sum(pointers_.size(), [&](std::size_t n) -> std::uint64_t {
      const Pointer& p = pointers_[n];
      if (p.leaf() || !collapsible(pointers_[std::size_t(p.left)], pointers_[std::size_t(p.right)])) return 0;
      marks_[n] = kMarkCollapse;
      return 1;
    });
  }

  Plan plan(bool allowExpand) override {
    const std::size_t count = pointers_.size();
    remap_.resize(count + 1);
    Plan plan;
    plan.changes = sum(count, [&](std::size_t n) -> std::uint64_t {
      const auto [emit, change] = emitOf(n, allowExpand);
      remap_[n] = emit;
      return change;
    });
    remap_[count] = 0;
    std::exclusive_scan(remap_.begin(), remap_.end(), remap_.begin(), std::uint32_t(0));
    plan.nodes = remap_[count];
    return plan;
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

  // The mark pass for one input voxel (tree_rules.glsl: markFor).
  std::uint64_t markFor(const InputVoxel& in, Op op) {
    const Cell c = unpackCell(in.xy, in.zd);
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

  // How many nodes n becomes, and whether that changes the tree (tree_rules.glsl: emitOf).
  std::pair<std::uint32_t, std::uint64_t> emitOf(std::size_t n, bool allowExpand) const {
    const Pointer& p = pointers_[n];
    if (removals_[n] > 0) return {0, 1};  // inside a reduced subtree
    if (p.parent >= 0 && markOf(std::size_t(p.parent)) == kMarkCollapse) return {0, 1};
    const Mark m = markOf(n);
    if (m == kMarkExpand) return allowExpand ? std::pair<std::uint32_t, std::uint64_t>{3, 1} : std::pair<std::uint32_t, std::uint64_t>{1, 0};
    return {1, m == kMarkReduce || m == kMarkCollapse ? 1 : 0};
  }

  // The restructure pass for one old node (tree_rules.glsl: writeNode).
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
    if (expand) {
      out.left = std::int32_t(o + 1), out.right = std::int32_t(o + 2);
    } else if (!p.leaf() && m != kMarkReduce && m != kMarkCollapse) {
      out.left = std::int32_t(remap_[std::size_t(p.left)]), out.right = std::int32_t(remap_[std::size_t(p.right)]);
    }
    spare_[o] = out;
    spareCells_[2 * o] = cells_[2 * n], spareCells_[2 * o + 1] = cells_[2 * n + 1];
    if (!expand) return;
    const Cell c = unpackCell(cells_[2 * n], cells_[2 * n + 1]);
    for (int k = 0; k < 2; ++k) {
      const std::uint32_t child = o + 1 + std::uint32_t(k);
      spare_[child] = Pointer{std::int32_t(o), kNone, kNone, childValue(p.value, scales_[c.depth])};
      const auto packed = packCell(childCell(c, k));
      spareCells_[2 * child] = packed[0], spareCells_[2 * child + 1] = packed[1];
    }
  }

  TreeFrame frame_;
  std::vector<float> scales_;
  std::vector<Pointer> pointers_, spare_;
  std::vector<std::uint32_t> cells_, spareCells_, marks_, remap_;
  std::vector<std::int32_t> removals_;  // ranges of reduced subtrees (plan)
  bool reduced_ = false;               // a reduce mark was set since the marks were cleared
  std::vector<InputVoxel> input_;
};

}  // namespace

std::unique_ptr<TreePasses> makeCpuTreePasses() { return std::make_unique<CpuTreePasses>(); }

}  // namespace isoatlas::levelset::dvt
