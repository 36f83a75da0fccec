#include "edit/dvt/dynamic_volume_tree.h"

#include <chrono>

#include "core/error.h"

namespace isoatlas::edit::dvt {
namespace {
double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

DynamicVolumeTree::DynamicVolumeTree(const VolumeTree& tree, std::unique_ptr<TreePasses> passes, const TreeOptions& options)
    : frame_(tree.frame), passes_(std::move(passes)), options_(options) {
  require(options.nodeLimit <= kMaxTreeNodes, "a node limit of " + std::to_string(options.nodeLimit) + " is more than a tree can index (" +
                                                  std::to_string(kMaxTreeNodes) + " nodes: its pointers are 32-bit)");
  require(tree.nodeCount() <= options.nodeLimit, "the tree has " + std::to_string(tree.nodeCount()) +
                                                     " nodes, more than the node limit " + std::to_string(options.nodeLimit));
  passes_->load(tree);
}

WriteStats DynamicVolumeTree::write(PreOrderInput input, Op op) {
  const auto start = std::chrono::steady_clock::now();
  WriteStats stats;
  stats.inputVoxels = input.size();
  passes_->setInput(std::move(input).take());
  bool allowExpand = true;
  std::optional<ChainRun> chained;
  if (options_.chainPasses) chained = passes_->writeChained(op, options_.nodeLimit);
  if (chained) stats.iterations = chained->iterations, stats.chainReads = chained->reads;
  for (; !chained || !chained->finished; ++stats.iterations) {
    // No marks: the voxels were written into leaves of their depth and nothing is left to change.
    if (passes_->mark(op) == 0) break;
    Plan plan = passes_->plan(allowExpand);
    if (plan.nodes > options_.nodeLimit) {
      // Over budget: finish what needs no new nodes (removals), so the streams end as a valid tree.
      allowExpand = false;
      plan = passes_->plan(false);
    }
    if (plan.changes == 0) break;
    passes_->restructure(plan, allowExpand, options_.nodeLimit);
    if (passes_->restructureFinishesWrites()) {
      ++stats.iterations;
      break;
    }
  }
  stats.nodes = passes_->nodeCount();
  stats.seconds = secondsSince(start);
  if (!allowExpand)
    throw Error("the edit needs more than the node limit of " + std::to_string(options_.nodeLimit) +
                    " nodes; it was applied only where it fitted (the tree is valid; use a smaller depth or a larger limit)",
                ErrorKind::Failure);
  if (options_.collapseEvery > 0 && ++writes_ % options_.collapseEvery == 0) {
    const auto collapseStart = std::chrono::steady_clock::now();
    collapse();
    stats.collapseSeconds = secondsSince(collapseStart);
    stats.collapsed = true;
    stats.nodes = passes_->nodeCount();
  }
  return stats;
}

std::uint64_t DynamicVolumeTree::collapse() {
  const std::uint64_t before = passes_->nodeCount();
  if (!options_.chainPasses || !passes_->collapseChained())
    while (passes_->markCollapse() > 0) passes_->restructure(passes_->plan(false), false, options_.nodeLimit);
  return before - passes_->nodeCount();
}

}  // namespace isoatlas::edit::dvt
