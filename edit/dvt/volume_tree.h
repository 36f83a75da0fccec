// VolumeTree: the dynamic volume tree (DVT) of Keller et al., as streams in pre-order.
//
// Space: a fixed box, split in halves along x, y, z in turn (depth 0 splits x, depth 1 y, depth 2 z,
// ...), so a node's cell follows from its depth and its integer coordinates along each axis. The box
// is a grid frame: voxels 0 .. 2^K - 1 along each axis of an indexed volume (TreeFrame), so depth 3K
// cells are its voxels, deeper cells sub-voxels. Only leaves hold values.
//
// Streams, one entry per node, in pre-order (a node, its left subtree, its right subtree):
//   pointers  parent, left, right (node indices; -1 none) and the value (leaves: see below; inner
//             nodes: unused)
//   cells     the node's cell: x | y << 16, z | depth << 16
// The remap stream (old index -> new index) lives only while a write runs (tree_backend.h).
//
// Values, "inside-ness" as everywhere in isoatlas (phi > 0 inside): the signed distance from the
// cell's centre to the surface, positive inside, over the cell's circumradius R(depth), clamped to
// [-1, 1] and never 0. +1: the whole cell is inside; -1: the whole cell is outside; in between: a
// narrow-band cell with a sub-voxel distance. A cell's centre is inside when its value is > 0.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec.h"

namespace isoatlas::edit::dvt {

inline constexpr int kMaxDepth = 48;           // 16 splits per axis: coordinates fit 16 bits
inline constexpr std::uint64_t kDefaultNodeLimit = std::uint64_t(1) << 26;  // a tree's, and a write's input voxels
// The most nodes a tree can hold: its pointers are 32-bit signed indices (on both backends).
inline constexpr std::uint64_t kMaxTreeNodes = (std::uint64_t(1) << 31) - 1;
inline constexpr std::int32_t kNone = -1;      // no parent (the root) or no children (a leaf)
inline constexpr float kInside = 1.0f, kOutside = -1.0f;
inline constexpr float kNearZero = 1e-6f;      // band values keep their sign: |value| >= this

struct Pointer {
  std::int32_t parent = kNone, left = kNone, right = kNone;
  float value = kOutside;
  bool leaf() const { return left < 0; }
  bool operator==(const Pointer&) const = default;
};

struct Cell {
  std::uint32_t x = 0, y = 0, z = 0, depth = 0;
  bool operator==(const Cell&) const = default;
};
// The node stream's packing of a cell (two uint32: x | y << 16, z | depth << 16).
inline std::array<std::uint32_t, 2> packCell(const Cell& c) { return {c.x | (c.y << 16), c.z | (c.depth << 16)}; }
inline Cell unpackCell(std::uint32_t xy, std::uint32_t zd) { return {xy & 0xffffu, xy >> 16, zd & 0xffffu, zd >> 16}; }

// How many times axis a (0 x, 1 y, 2 z) has been split above depth d.
inline std::uint32_t splitsOf(int axis, std::uint32_t depth) { return (depth + 2 - std::uint32_t(axis)) / 3; }
// The axis the node at depth d splits.
inline int splitAxis(std::uint32_t depth) { return int(depth % 3); }
// Child 0 (lower half) or 1 of `c` along its split axis.
inline Cell childCell(const Cell& c, int which) {
  Cell child = c;
  child.depth = c.depth + 1;
  std::uint32_t& coordinate = splitAxis(c.depth) == 0 ? child.x : (splitAxis(c.depth) == 1 ? child.y : child.z);
  coordinate = 2 * coordinate + std::uint32_t(which);
  return child;
}
// The depth-d ancestor of `c` (d <= c.depth).
inline Cell ancestorAt(const Cell& c, std::uint32_t d) {
  return {c.x >> (splitsOf(0, c.depth) - splitsOf(0, d)), c.y >> (splitsOf(1, c.depth) - splitsOf(1, d)),
          c.z >> (splitsOf(2, c.depth) - splitsOf(2, d)), d};
}
// The child (0 or 1) of the depth-d ancestor of `c` that contains `c` (d < c.depth).
inline int childTowards(const Cell& c, std::uint32_t d) {
  const int axis = splitAxis(d);
  const std::uint32_t coordinate = axis == 0 ? c.x : (axis == 1 ? c.y : c.z);
  // The split at depth d decides bit (splits below d) of the coordinate, counted from its low end.
  return int((coordinate >> (splitsOf(axis, c.depth) - 1 - splitsOf(axis, d))) & 1u);
}

// The box: the voxels 0 .. 2^K - 1 of a grid along each axis, its world placement as a Volume's.
struct TreeFrame {
  int voxelSplits = 8;  // K
  Vec3 spacing{1, 1, 1}, origin{0, 0, 0};
  Mat3 direction;
  // The source volume's voxels along each axis, from voxel 0 (frameOf); 0: the whole box, 2^K.
  std::array<std::int64_t, 3> extent{0, 0, 0};
  std::int64_t voxelsPerAxis() const { return std::int64_t(1) << voxelSplits; }
  // The voxel grid a mask of the tree has: the source's (extent), else the box's.
  std::array<std::int64_t, 3> grid() const {
    std::array<std::int64_t, 3> g;
    for (int a = 0; a < 3; ++a) g[a] = extent[a] > 0 ? extent[a] : voxelsPerAxis();
    return g;
  }
  std::uint32_t voxelDepth() const { return std::uint32_t(3 * voxelSplits); }  // depth of cells = voxels
  // A point in voxel index coordinates in the world (as Volume::indexToWorld).
  Vec3 indexToWorld(const Vec3& i) const { return origin + direction * Vec3{i.x * spacing.x, i.y * spacing.y, i.z * spacing.z}; }
  // The cell's centre in voxel index coordinates and in the world.
  Vec3 centreIndex(const Cell& c) const {
    const Vec3 s = cellVoxels(c.depth);
    return {(c.x + 0.5) * s.x - 0.5, (c.y + 0.5) * s.y - 0.5, (c.z + 0.5) * s.z - 0.5};
  }
  Vec3 centreWorld(const Cell& c) const { return indexToWorld(centreIndex(c)); }
  // The cell's size in voxels along each axis (fractional below the voxels): 2^(K - splits), exactly.
  Vec3 cellVoxels(std::uint32_t depth) const {
    Vec3 s;
    for (int a = 0; a < 3; ++a) {
      const int e = voxelSplits - int(splitsOf(a, depth));
      s[a] = e >= 0 ? double(std::uint64_t(1) << e) : 1.0 / double(std::uint64_t(1) << -e);
    }
    return s;
  }
  // Circumradius of a depth-d cell in world units (the largest centre-to-corner distance).
  double radius(std::uint32_t depth) const;
  bool operator==(const TreeFrame&) const = default;
};

struct VolumeTree {
  TreeFrame frame;
  std::vector<Pointer> pointers;      // the pointer stream
  std::vector<std::uint32_t> cells;   // the node stream, two values per node (packCell)

  static VolumeTree empty(const TreeFrame& frame);  // one outside root
  std::size_t nodeCount() const { return pointers.size(); }
  Cell cell(std::size_t n) const { return unpackCell(cells[2 * n], cells[2 * n + 1]); }
  std::size_t leafCount() const;
  std::uint32_t maxDepth() const;
  std::uint64_t bytes() const { return pointers.size() * sizeof(Pointer) + cells.size() * 4; }
  bool operator==(const VolumeTree&) const = default;
};

// What is wrong with a tree's streams, or "" when sound: pre-order layout (left = n + 1, right after
// the left subtree), parent and child pointers agreeing, children's cells the halves of their
// parent's, depths within kMaxDepth, values finite in [-1, 1] and nonzero.
std::string treeProblem(const VolumeTree& tree);

}  // namespace isoatlas::edit::dvt
