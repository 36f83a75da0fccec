#include "edit/solids/rasterise.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>

#include "core/error.h"

namespace isoatlas::edit::dvt {
namespace {

using Radii = std::array<double, kMaxDepth + 1>;  // the circumradius of a cell, by depth
Radii radiiOf(const TreeFrame& frame) {
  Radii r;
  for (std::uint32_t d = 0; d <= std::uint32_t(kMaxDepth); ++d) r[d] = frame.radius(d);
  return r;
}

// The voxels made so far, counted in batches so that threads seldom meet at the shared counter.
struct VoxelBudget {
  static constexpr std::size_t kBatch = 4096;
  std::uint64_t limit;
  std::atomic<std::uint64_t> used{0};
  std::atomic<bool> over{false};
  void add(std::uint64_t n) {
    if (used.fetch_add(n, std::memory_order_relaxed) + n > limit) over.store(true, std::memory_order_relaxed);
  }
  bool spent() const { return over.load(std::memory_order_relaxed); }
};

std::string tooManyVoxels(std::uint32_t depth, std::uint64_t limit) {
  return "the shape makes more than " + std::to_string(limit) + " voxels at depth " + std::to_string(depth) +
         " (the node limit); choose a smaller depth or a larger node limit";
}

struct Rasteriser {
  const Solid& solid;
  const DistanceSolid* distance;  // when the solid is one: classified from centres kept while splitting
  const TreeFrame& frame;
  std::uint32_t target;
  bool hierarchical;
  Radii radius;
  std::array<Vec3, kMaxDepth + 1> childOffset;  // from a depth-d cell's centre to its upper child's
  VoxelBudget& budget;

  void emit(std::vector<InputVoxel>& out, const InputVoxel& voxel) const {
    out.push_back(voxel);
    if (out.size() % VoxelBudget::kBatch == 0) budget.add(VoxelBudget::kBatch);
  }

  CellClass classify(const Cell& cell, const Vec3& centre, float& value) const {
    const double r = radius[cell.depth];
    if (distance) return distance->classifyAt(centre, r, cell.depth == target ? &value : nullptr);
    return cell.depth == target ? solid.classifyWithValue(frame, cell, r, value) : solid.classify(frame, cell, r);
  }

  // The voxels of `cell`'s subtree (its centre in the world), depth first.
  void visit(const Cell& cell, const Vec3& centre, std::vector<InputVoxel>& out) const {
    if (budget.spent()) return;
    float v = kInside;
    const CellClass k = classify(cell, centre, v);
    if (k == CellClass::Outside) return;
    if (cell.depth == target) {
      if (v > kOutside) emit(out, inputVoxel(cell, v));
      return;
    }
    if (k == CellClass::Inside && hierarchical) {
      emit(out, inputVoxel(cell, kInside));
      return;
    }
    visit(childCell(cell, 0), centre - childOffset[cell.depth], out);
    visit(childCell(cell, 1), centre + childOffset[cell.depth], out);
  }
};

// The top of the tree, depth first on one thread: wholly inside or outside cells end there, as they
// would below, and each crossed cell of depth `top` keeps a place for the voxels of its subtree.
// Deep enough for many crossed cells to share among the threads, even for a brush of few top cells.
struct TopCells {
  struct Item {
    InputVoxel voxel;
    bool crossed = false;  // a place for the voxels of `cell`
    Cell cell;
  };
  std::uint32_t top;
  std::vector<Item> items;

  TopCells(const Solid& solid, const TreeFrame& frame, std::uint32_t targetDepth, bool hierarchical)
      : top(std::min<std::uint32_t>(targetDepth, std::max<std::uint32_t>(9, targetDepth > 15 ? targetDepth - 15 : 0))) {
    const Radii radius = radiiOf(frame);
    const auto visit = [&](const auto& self, const Cell& c) -> void {
      const CellClass k = solid.classify(frame, c, radius[c.depth]);
      if (k == CellClass::Outside) return;
      if (c.depth == top) return items.push_back({{}, true, c});
      if (k == CellClass::Inside && hierarchical) return items.push_back({inputVoxel(c, kInside), false, c});
      self(self, childCell(c, 0));
      self(self, childCell(c, 1));
    };
    visit(visit, Cell{});
  }
};

}  // namespace

void checkVoxelBudget(const Solid& solid, const TreeFrame& frame, std::uint32_t targetDepth, bool hierarchical, std::uint64_t voxelLimit) {
  require(targetDepth <= std::uint32_t(kMaxDepth),
          "depth " + std::to_string(targetDepth) + " is past the tree's limit of " + std::to_string(kMaxDepth));
  // Level by level down to at most 64^3 cells, counting the cells that make voxels below them
  // (crossed ones; with flat rasterisation inside ones too).
  const std::uint32_t last = std::min<std::uint32_t>(targetDepth, 18);
  std::vector<std::uint64_t> counts(last + 1, 0);
  std::vector<Cell> level{Cell{}};
  for (std::uint32_t d = 0; d <= last && !level.empty(); ++d) {
    const double radius = frame.radius(d);
    std::vector<Cell> next;
    for (const Cell& c : level) {
      const CellClass k = solid.classify(frame, c, radius);
      if (k == CellClass::Outside || (k == CellClass::Inside && hierarchical)) continue;
      ++counts[d];
      if (d < last) next.push_back(childCell(c, 0)), next.push_back(childCell(c, 1));
    }
    level = std::move(next);
  }
  // Extrapolated with the growth of the last three levels, at most a surface's (x4 every 3 levels)
  // or, flat, a volume's (x8): thin shapes grow as curves or points until they are resolved.
  double estimate = double(counts[last]);
  if (last < targetDepth && last >= 3 && counts[last - 3] > 0) {
    const double growth = std::clamp(double(counts[last]) / double(counts[last - 3]), 1.0, hierarchical ? 4.0 : 8.0);
    estimate *= std::pow(growth, double(targetDepth - last) / 3.0);
  }
  // A margin for shapes that grow faster than foretold: those in it are counted exactly as they are made.
  if (estimate > 2.0 * double(voxelLimit)) throw Error(tooManyVoxels(targetDepth, voxelLimit));
}

PreOrderInput rasterise(const Solid& solid, const TreeFrame& frame, std::uint32_t targetDepth, bool hierarchical,
                        std::uint64_t voxelLimit) {
  checkVoxelBudget(solid, frame, targetDepth, hierarchical, voxelLimit);
  const TopCells top(solid, frame, targetDepth, hierarchical);
  VoxelBudget budget{.limit = voxelLimit};
  Rasteriser r{solid, dynamic_cast<const DistanceSolid*>(&solid), frame, targetDepth, hierarchical, radiiOf(frame), {}, budget};
  for (std::uint32_t d = 0; d <= std::uint32_t(kMaxDepth); ++d) {
    const int a = splitAxis(d);  // the children's centres a quarter of the cell along the split axis
    Vec3 step{0, 0, 0};
    step[a] = frame.spacing[a] * frame.cellVoxels(d)[a] / 4;
    r.childOffset[d] = frame.direction * step;
  }
  // The crossed top cells rasterised in parallel, their voxels put in their places: the whole comes
  // out in pre-order.
  const auto& items = top.items;
  std::vector<std::vector<InputVoxel>> parts(items.size());
  tbb::parallel_for(std::size_t(0), items.size(), [&](std::size_t i) {
    if (items[i].crossed) {
      r.visit(items[i].cell, frame.centreWorld(items[i].cell), parts[i]);
      budget.add(parts[i].size() % VoxelBudget::kBatch);  // what emit's batches left uncounted
    } else {
      parts[i] = {items[i].voxel};
    }
  });
  std::vector<std::size_t> at(parts.size() + 1, 0);
  for (std::size_t i = 0; i < parts.size(); ++i) at[i + 1] = at[i] + parts[i].size();
  if (budget.spent() || at.back() > voxelLimit) throw Error(tooManyVoxels(targetDepth, voxelLimit));
  std::vector<InputVoxel> out(at.back());
  tbb::parallel_for(std::size_t(0), parts.size(), [&](std::size_t i) { std::copy(parts[i].begin(), parts[i].end(), out.begin() + std::ptrdiff_t(at[i])); });
  return PreOrderInput::madeInPreOrder(std::move(out));
}

}  // namespace isoatlas::edit::dvt
