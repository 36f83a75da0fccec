#include "levelset/dvt/rasterise.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <array>

#include "core/error.h"

namespace isoatlas::levelset::dvt {
namespace {

struct Rasteriser {
  const Solid& solid;
  const TreeFrame& frame;
  std::uint32_t target;
  bool hierarchical;
  std::array<double, kMaxDepth + 1> radius;

  // The voxels of `cell`'s subtree, depth first.
  void visit(const Cell& cell, std::vector<InputVoxel>& out) const {
    const CellClass k = solid.classify(frame, cell, radius[cell.depth]);
    if (k == CellClass::Outside) return;
    if (cell.depth == target) {
      const float v = k == CellClass::Inside ? kInside : solid.value(frame, cell, radius[cell.depth]);
      if (v > kOutside) out.push_back(inputVoxel(cell, v));
      return;
    }
    if (k == CellClass::Inside && hierarchical) {
      out.push_back(inputVoxel(cell, kInside));
      return;
    }
    visit(childCell(cell, 0), out);
    visit(childCell(cell, 1), out);
  }
};

}  // namespace

std::vector<InputVoxel> rasterise(const Solid& solid, const TreeFrame& frame, std::uint32_t targetDepth, bool hierarchical) {
  require(targetDepth <= std::uint32_t(kMaxDepth),
          "depth " + std::to_string(targetDepth) + " is past the tree's limit of " + std::to_string(kMaxDepth));
  Rasteriser r{solid, frame, targetDepth, hierarchical, {}};
  for (std::uint32_t d = 0; d <= std::uint32_t(kMaxDepth); ++d) r.radius[d] = frame.radius(d);
  // The top of the tree level by level on this thread (wholly inside or outside cells end there, as
  // they would below), then the crossed cells of depth `top` in parallel, their results in order.
  const std::uint32_t top = std::min<std::uint32_t>(targetDepth, 9);
  std::vector<InputVoxel> out;
  std::vector<Cell> cells{Cell{}};
  for (std::uint32_t d = 0; d < top; ++d) {
    std::vector<Cell> next;
    next.reserve(cells.size() * 2);
    for (const Cell& c : cells) {
      const CellClass k = solid.classify(frame, c, r.radius[c.depth]);
      if (k == CellClass::Outside) continue;
      if (k == CellClass::Inside && hierarchical) {
        out.push_back(inputVoxel(c, kInside));
        continue;
      }
      next.push_back(childCell(c, 0)), next.push_back(childCell(c, 1));
    }
    cells = std::move(next);
  }
  std::vector<std::vector<InputVoxel>> parts(cells.size());
  tbb::parallel_for(std::size_t(0), cells.size(), [&](std::size_t i) { r.visit(cells[i], parts[i]); });
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  sortInPreOrder(out);  // the cells wholly inside from the top levels came first
  return out;
}

}  // namespace isoatlas::levelset::dvt
