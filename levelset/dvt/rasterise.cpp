#include "levelset/dvt/rasterise.h"

#include <tbb/parallel_for.h>

#include <array>

#include "core/error.h"

namespace isoatlas::levelset::dvt {
namespace {

struct Rasteriser {
  const Solid& solid;
  const DistanceSolid* distance;  // when the solid is one: classified from centres kept while splitting
  const TreeFrame& frame;
  std::uint32_t target;
  bool hierarchical;
  std::array<double, kMaxDepth + 1> radius;
  std::array<Vec3, kMaxDepth + 1> childOffset;  // from a depth-d cell's centre to its upper child's

  CellClass classify(const Cell& cell, const Vec3& centre, float& value) const {
    const double r = radius[cell.depth];
    if (distance) return distance->classifyAt(centre, r, cell.depth == target ? &value : nullptr);
    return cell.depth == target ? solid.classifyWithValue(frame, cell, r, value) : solid.classify(frame, cell, r);
  }

  // The voxels of `cell`'s subtree (its centre in the world), depth first.
  void visit(const Cell& cell, const Vec3& centre, std::vector<InputVoxel>& out) const {
    float v = kInside;
    const CellClass k = classify(cell, centre, v);
    if (k == CellClass::Outside) return;
    if (cell.depth == target) {
      if (v > kOutside) out.push_back(inputVoxel(cell, v));
      return;
    }
    if (k == CellClass::Inside && hierarchical) {
      out.push_back(inputVoxel(cell, kInside));
      return;
    }
    visit(childCell(cell, 0), centre - childOffset[cell.depth], out);
    visit(childCell(cell, 1), centre + childOffset[cell.depth], out);
  }
};

}  // namespace

PreOrderInput rasterise(const Solid& solid, const TreeFrame& frame, std::uint32_t targetDepth, bool hierarchical) {
  require(targetDepth <= std::uint32_t(kMaxDepth),
          "depth " + std::to_string(targetDepth) + " is past the tree's limit of " + std::to_string(kMaxDepth));
  Rasteriser r{solid, dynamic_cast<const DistanceSolid*>(&solid), frame, targetDepth, hierarchical, {}, {}};
  for (std::uint32_t d = 0; d <= std::uint32_t(kMaxDepth); ++d) {
    r.radius[d] = frame.radius(d);
    const int a = splitAxis(d);  // the children's centres a quarter of the cell along the split axis
    Vec3 step{0, 0, 0};
    step[a] = frame.spacing[a] * frame.cellVoxels(d)[a] / 4;
    r.childOffset[d] = frame.direction * step;
  }
  // The top of the tree depth first on this thread (wholly inside or outside cells end there, as they
  // would below), keeping a place for each crossed cell of depth `top`; those are then rasterised in
  // parallel and their voxels put in their places, so the whole comes out in pre-order.
  // Deep enough for many crossed cells to share among the threads, even for a brush of few top cells.
  const std::uint32_t top = std::min<std::uint32_t>(targetDepth, std::max<std::uint32_t>(9, targetDepth > 15 ? targetDepth - 15 : 0));
  struct Item {
    InputVoxel voxel;
    bool crossed = false;  // a place for the voxels of `cell`
    Cell cell;
  };
  std::vector<Item> items;
  const auto visitTop = [&](const auto& self, const Cell& c) -> void {
    const CellClass k = solid.classify(frame, c, r.radius[c.depth]);
    if (k == CellClass::Outside) return;
    if (c.depth == top) return items.push_back({{}, true, c});
    if (k == CellClass::Inside && hierarchical) return items.push_back({inputVoxel(c, kInside), false, c});
    self(self, childCell(c, 0));
    self(self, childCell(c, 1));
  };
  visitTop(visitTop, Cell{});
  std::vector<std::vector<InputVoxel>> parts(items.size());
  tbb::parallel_for(std::size_t(0), items.size(), [&](std::size_t i) {
    if (items[i].crossed) r.visit(items[i].cell, frame.centreWorld(items[i].cell), parts[i]);
    else parts[i] = {items[i].voxel};
  });
  std::vector<std::size_t> at(parts.size() + 1, 0);
  for (std::size_t i = 0; i < parts.size(); ++i) at[i + 1] = at[i] + parts[i].size();
  std::vector<InputVoxel> out(at.back());
  tbb::parallel_for(std::size_t(0), parts.size(), [&](std::size_t i) { std::copy(parts[i].begin(), parts[i].end(), out.begin() + std::ptrdiff_t(at[i])); });
  return PreOrderInput::madeInPreOrder(std::move(out));
}

}  // namespace isoatlas::levelset::dvt
