#include "edit/dvt/volume_tree.h"

#include <algorithm>
#include <cmath>

namespace isoatlas::edit::dvt {

double TreeFrame::radius(std::uint32_t depth) const {
  const Vec3 s = cellVoxels(depth);
  double r = 0;
  for (int corner = 0; corner < 4; ++corner) {  // the other four are these negated
    const Vec3 half{0.5 * s.x * spacing.x, (corner & 1 ? -0.5 : 0.5) * s.y * spacing.y, (corner & 2 ? -0.5 : 0.5) * s.z * spacing.z};
    r = std::max(r, norm(direction * half));
  }
  return r;
}

VolumeTree VolumeTree::empty(const TreeFrame& frame) {
  VolumeTree t;
  t.frame = frame;
  t.pointers = {Pointer{}};
  const auto packed = packCell(Cell{});
  t.cells = {packed[0], packed[1]};
  return t;
}

std::size_t VolumeTree::leafCount() const {
  return std::size_t(std::count_if(pointers.begin(), pointers.end(), [](const Pointer& p) { return p.leaf(); }));
}

std::uint32_t VolumeTree::maxDepth() const {
  std::uint32_t d = 0;
  for (std::size_t n = 0; n < nodeCount(); ++n) d = std::max(d, cells[2 * n + 1] >> 16);
  return d;
}

std::string treeProblem(const VolumeTree& tree) {
  const std::size_t count = tree.nodeCount();
  if (count == 0) return "the tree has no root";
  if (tree.cells.size() != 2 * count) return "the node stream's length does not match the pointer stream's";
  if (tree.frame.voxelSplits < 0 || tree.frame.voxelSplits > kMaxDepth / 3) return "the frame's voxel splits are out of range";
  for (const std::int64_t e : tree.frame.extent)
    if (e < 0 || e > tree.frame.voxelsPerAxis()) return "the frame's extent is outside its box";
  if (tree.pointers[0].parent != kNone || !(tree.cell(0) == Cell{})) return "node 0 is not the root";
  // Walk the pre-order layout with an explicit stack.
  std::vector<std::size_t> stack{0};
  std::size_t next = 0;  // the index the walk expects next
  while (!stack.empty()) {
    const std::size_t n = stack.back();
    stack.pop_back();
    const std::string at = "node " + std::to_string(n) + ": ";
    if (n != next) return at + "not in pre-order";
    ++next;
    const Pointer& p = tree.pointers[n];
    const Cell c = tree.cell(n);
    if (c.depth > std::uint32_t(kMaxDepth)) return at + "deeper than the depth limit";
    if (!std::isfinite(p.value) || p.value < kOutside || p.value > kInside || p.value == 0.0f)
      return at + "value out of [-1, 1] or zero";
    if (p.leaf()) {
      if (p.right != kNone || p.left != kNone) return at + "a leaf with one child";
      continue;
    }
    if (std::size_t(p.left) != n + 1 || p.right <= p.left || std::size_t(p.right) >= count) return at + "children not in pre-order";
    for (int k = 0; k < 2; ++k) {
      const std::size_t child = std::size_t(k == 0 ? p.left : p.right);
      if (tree.pointers[child].parent != std::int32_t(n)) return at + "child " + std::to_string(child) + " names another parent";
      if (!(tree.cell(child) == childCell(c, k))) return at + "child " + std::to_string(child) + " is not its half";
    }
    stack.push_back(std::size_t(p.right));
    stack.push_back(std::size_t(p.left));
  }
  if (next != count) return "nodes " + std::to_string(next) + " .. " + std::to_string(count - 1) + " are outside the tree";
  return "";
}

}  // namespace isoatlas::edit::dvt
