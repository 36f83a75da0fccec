// The per-node rules of a DVT write and collapse (Keller et al., sec. 4.2-4.3), shared by the CPU passes
// (cpu_tree_passes) and, through the defines of ruleDefines(), their GLSL twin
// edit/dvt/shaders/tree_rules.glsl, so the two backends make the same streams bit for bit.
#pragma once
#include <algorithm>
#include <bit>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "edit/dvt/volume_tree.h"

namespace isoatlas::edit::dvt {

enum class Op : std::uint32_t { Union = 0, Subtract = 1 };

// The most levels one GPU restructure adds below an expanded leaf (EXPAND_LEVELS): its new subtree is
// at most 2^9 - 2 nodes, made by one thread (llvmpipe ends a shader's loops after 65535 turns). The
// CPU passes have no such limit (kMaxDepth).
inline constexpr std::uint32_t kExpandLevels = 8;

// What the mark pass asks of a node (tree_rules.glsl: MARK_*).
enum Mark : std::uint32_t { kMarkNone = 0, kMarkExpand = 1, kMarkReduce = 2, kMarkCollapse = 3 };

// One voxel of an input: its cell (packed as in the node stream) at its target depth and its value
// (volume_tree.h). Inputs of one write are disjoint cells holding some inside (value > -1).
struct InputVoxel {
  std::uint32_t xy = 0, zd = 0;
  float value = kInside;
  std::uint32_t unused = 0;  // 16 bytes, as the GPU reads it
};
InputVoxel inputVoxel(const Cell& c, float value);

// The value an input voxel brings to a leaf: the input's own for a union, its complement for a
// subtraction (inside-ness of "not in the input").
inline float inputValue(Op op, float value) { return op == Op::Union ? value : -value; }
// A leaf's value after the write (both arguments already as inputValue gives them).
inline float combined(Op op, float leaf, float incoming) {
  return op == Op::Union ? std::max(leaf, incoming) : std::min(leaf, incoming);
}
// A leaf no input of this kind can change (so a coarser leaf need not be expanded).
inline bool saturated(Op op, float leaf) { return op == Op::Union ? leaf == kInside : leaf == kOutside; }
// A child's value when its parent leaf is split: the parent's distance measured in the child's radius.
inline float childValue(float parent, float scale) { return std::clamp(parent * scale, kOutside, kInside); }
// The depth an expanded leaf's new subtree is cut at: `levels` below the leaf (at most kMaxDepth), or
// sooner, at the first depth whose value (childValue down from the leaf's, `scales` from childScales)
// no input can change: such a node is not split, as splitting a level at a time would not split it.
// So the tree after a write does not depend on how many levels one restructure adds.
inline std::uint32_t expansionCut(Op op, float leafValue, std::uint32_t leafDepth, std::uint32_t levels, const float* scales) {
  const std::uint32_t last = std::min<std::uint32_t>(leafDepth + levels, std::uint32_t(kMaxDepth));
  float v = leafValue;
  for (std::uint32_t d = leafDepth; d < last; ++d) {
    v = childValue(v, scales[d]);
    if (saturated(op, v)) return d + 1;
  }
  return last;
}
// Two sibling leaves one leaf can stand for (the redundancy optimisation): equal and uniform.
inline bool collapsible(const Pointer& left, const Pointer& right) {
  return left.leaf() && right.leaf() && left.value == right.value && (left.value == kInside || left.value == kOutside);
}

// The position of a cell in pre-order (its path of child choices from the root, left-aligned in 48
// bits): a write's voxels come sorted by it, so the voxels inside one leaf are next to each other.
std::uint64_t preOrderKey(const Cell& c);
bool inPreOrder(const std::vector<InputVoxel>& input);

// A write's input: disjoint voxels in pre-order. From any voxels (sorted by preOrderKey unless they
// already are in order), or from rasterise, which makes them in pre-order.
class PreOrderInput {
public:
  explicit PreOrderInput(std::vector<InputVoxel> voxels);
  static PreOrderInput madeInPreOrder(std::vector<InputVoxel> voxels) { return PreOrderInput(std::move(voxels), 0); }
  const std::vector<InputVoxel>& voxels() const { return voxels_; }
  std::size_t size() const { return voxels_.size(); }
  std::vector<InputVoxel> take() && { return std::move(voxels_); }

private:
  PreOrderInput(std::vector<InputVoxel> voxels, int) : voxels_(std::move(voxels)) {}
  std::vector<InputVoxel> voxels_;
};

// The depth of the deepest common ancestor of two cells of which neither contains the other.
inline std::uint32_t commonDepth(const Cell& a, const Cell& b) {
  // Per axis, the first split where the two coordinates part (the split of axis k numbered s is at
  // depth 3s + k); the paths part at the shallowest of those, or end at the shallower cell.
  std::uint32_t d = std::min(a.depth, b.depth);
  const std::uint32_t ca[3] = {a.x, a.y, a.z}, cb[3] = {b.x, b.y, b.z};
  for (std::uint32_t k = 0; k < 3; ++k) {
    const std::uint32_t sa = splitsOf(int(k), a.depth), sb = splitsOf(int(k), b.depth), s = std::min(sa, sb);
    const std::uint32_t differ = (ca[k] >> (sa - s)) ^ (cb[k] >> (sb - s));
    if (differ != 0) d = std::min(d, 3 * (s - std::uint32_t(std::bit_width(differ))) + k);
  }
  return d;
}

// Per depth d, R(d) / R(d + 1) (childValue's scale), as floats both backends read.
std::vector<float> childScales(const TreeFrame& frame);

// The constants above as GLSL defines.
std::vector<std::pair<std::string, std::string>> ruleDefines();

}  // namespace isoatlas::edit::dvt
