#include "edit/dvt/cpu_tree_stream.h"

namespace isoatlas::edit::dvt::cpu {
namespace {

struct Loader {
  const std::uint32_t brickDepth;
  PairPool<TopNode>& top;
  PairPool<Brick>& bricks;
  std::uint64_t &topNodes, &brickNodes;

  // The stream's subtree [n, end) at depth `depth` into top node t.
  void loadTop(const VolumeTree& tree, std::size_t n, std::size_t end, std::int32_t t) {
    const Pointer& p = tree.pointers[n];
    ++topNodes;
    {
      TopNode& node = top.items[std::size_t(t)];
      node.xy = tree.cells[2 * n], node.zd = tree.cells[2 * n + 1], node.value = p.value;
    }
    if (p.leaf()) return;
    const std::uint32_t depth = tree.cell(n).depth;
    const auto left = std::size_t(p.left), right = std::size_t(p.right);
    if (depth + 1 == brickDepth) {
      const std::int32_t pair = bricks.allocate();
      loadBrick(tree, left, right, bricks.items[std::size_t(pair)]);
      loadBrick(tree, right, end, bricks.items[std::size_t(pair) + 1]);
      top.items[std::size_t(t)].children = pair;
      return;
    }
    const std::int32_t pair = top.allocate();
    top.items[std::size_t(t)].children = pair;
    loadTop(tree, left, right, pair);
    loadTop(tree, right, end, pair + 1);
  }

  void loadBrick(const VolumeTree& tree, std::size_t begin, std::size_t end, Brick& brick) {
    brick.nodes.resize(end - begin);
    for (std::size_t n = begin; n < end; ++n) {
      const Pointer& p = tree.pointers[n];
      brick.nodes[n - begin] = {p.leaf() ? kNone : p.right - std::int32_t(begin), p.value};
    }
    brick.root = tree.cell(begin);
    brickNodes += brick.size();
  }
};

struct Emitter {
  const std::uint32_t brickDepth;
  const PairPool<TopNode>& top;
  const PairPool<Brick>& bricks;

  // Top node t and its subtree appended to the stream in pre-order; returns t's index there.
  std::int32_t emitTop(VolumeTree& out, std::int32_t t, std::int32_t parent) const {
    const TopNode& n = top.items[std::size_t(t)];
    const auto o = std::int32_t(out.pointers.size());
    out.pointers.push_back({parent, kNone, kNone, n.value});
    out.cells.push_back(n.xy), out.cells.push_back(n.zd);
    if (n.leaf()) return o;
    std::int32_t left = 0, right = 0;
    if (n.cell().depth + 1 == brickDepth) {
      left = emitBrick(out, bricks.items[std::size_t(n.children)], o);
      right = emitBrick(out, bricks.items[std::size_t(n.children) + 1], o);
    } else {
      left = emitTop(out, n.children, o);
      right = emitTop(out, n.children + 1, o);
    }
    out.pointers[std::size_t(o)].left = left, out.pointers[std::size_t(o)].right = right;
    return o;
  }

  static std::int32_t emitBrick(VolumeTree& out, const Brick& b, std::int32_t parent) {
    // Parents and cells down from the root's: children come after their parents in pre-order.
    const auto base = std::int32_t(out.pointers.size());
    out.pointers.resize(out.pointers.size() + b.size());
    out.cells.resize(out.cells.size() + 2 * b.size());
    Pointer* pointers = out.pointers.data() + base;
    std::uint32_t* cells = out.cells.data() + 2 * std::size_t(base);
    const auto root = packCell(b.root);
    cells[0] = root[0], cells[1] = root[1];
    pointers[0].parent = parent;
    for (std::size_t n = 0; n < b.size(); ++n) {
      const BrickNode& node = b.nodes[n];
      pointers[n].value = node.value;
      if (node.leaf()) continue;
      const std::size_t children[2] = {n + 1, std::size_t(node.right)};
      pointers[n].left = base + std::int32_t(children[0]), pointers[n].right = base + node.right;
      const Cell c = unpackCell(cells[2 * n], cells[2 * n + 1]);
      for (int k = 0; k < 2; ++k) {
        const auto child = packCell(childCell(c, k));
        cells[2 * children[k]] = child[0], cells[2 * children[k] + 1] = child[1];
        pointers[children[k]].parent = base + std::int32_t(n);
      }
    }
    return base;
  }
};

}  // namespace

void loadStream(const VolumeTree& tree, std::uint32_t brickDepth, PairPool<TopNode>& top, PairPool<Brick>& bricks,
                std::uint64_t& topNodes, std::uint64_t& brickNodes) {
  Loader{brickDepth, top, bricks, topNodes, brickNodes}.loadTop(tree, 0, tree.nodeCount(), 0);
}

void appendStream(VolumeTree& out, std::uint32_t brickDepth, const PairPool<TopNode>& top, const PairPool<Brick>& bricks) {
  Emitter{brickDepth, top, bricks}.emitTop(out, 0, kNone);
}

}  // namespace isoatlas::edit::dvt::cpu
