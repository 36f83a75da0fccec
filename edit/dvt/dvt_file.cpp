#include "edit/dvt/dvt_file.h"

#include <cmath>

#include "core/sectioned_file.h"

namespace isoatlas::edit::dvt {
namespace {
constexpr char kMagic[8] = {'I', 'S', 'O', 'A', '-', 'D', 'V', 'T'};
constexpr std::size_t kNodeBytes = 24;
}  // namespace

void writeDvt(const std::string& path, const VolumeTree& tree) {
  const std::string problem = treeProblem(tree);
  require(problem.empty(), path + ": the tree is not sound (" + problem + ")");
  SectionedFileWriter out(path, kMagic, kDvtVersion);
  SectionWriter frame;
  frame.put(std::uint32_t(tree.frame.voxelSplits));
  frame.putVec(tree.frame.spacing), frame.putVec(tree.frame.origin);
  for (const auto& row : tree.frame.direction.m)
    for (const double x : row) frame.put(x);
  out.section("FRAM", frame);
  if (tree.frame.extent != std::array<std::int64_t, 3>{0, 0, 0}) {
    SectionWriter grid;
    for (const std::int64_t e : tree.frame.grid()) grid.put(std::uint64_t(e));
    out.section("GRID", grid);
  }
  SectionWriter nodes;
  nodes.bytes.reserve(8 + tree.nodeCount() * kNodeBytes);
  nodes.put(std::uint64_t(tree.nodeCount()));
  for (std::size_t n = 0; n < tree.nodeCount(); ++n) {
    const Pointer& p = tree.pointers[n];
    nodes.put(p.parent), nodes.put(p.left), nodes.put(p.right), nodes.put(p.value);
    nodes.put(tree.cells[2 * n]), nodes.put(tree.cells[2 * n + 1]);
  }
  out.section("NODE", nodes);
  out.finish();
}

VolumeTree readDvt(const std::string& path, bool checksums) {
  const SectionedFile file = readSectionedFile(path, kMagic, "a volume tree file (.dvt)");
  if (file.version != kDvtVersion)
    throw Error(path + ": .dvt format version " + std::to_string(file.version) + " (this isoatlas reads version " +
                std::to_string(kDvtVersion) + ")");
  VolumeTree tree;
  bool frame = false, grid = false, nodes = false;
  forEachSection(file, checksums, [&](const std::string& tag, SectionReader& r) {
    if (tag == "FRAM") {
      if (frame) r.fail("a second FRAM section");
      frame = true;
      const std::uint32_t k = r.get<std::uint32_t>();
      if (k > std::uint32_t(kMaxDepth / 3)) r.fail("voxel splits " + std::to_string(k) + " (at most " + std::to_string(kMaxDepth / 3) + ")");
      tree.frame.voxelSplits = int(k);
      tree.frame.spacing = r.vec(), tree.frame.origin = r.vec();
      if (!(tree.frame.spacing.x > 0 && tree.frame.spacing.y > 0 && tree.frame.spacing.z > 0)) r.fail("a spacing is not > 0");
      for (auto& row : tree.frame.direction.m)
        for (double& x : row) x = r.finite<double>();
      const double r0 = tree.frame.radius(0), rDeepest = tree.frame.radius(kMaxDepth + 1);
      if (!(std::isfinite(r0) && rDeepest > 0)) r.fail("the frame's cells have no extent (spacing or direction)");
    } else if (tag == "GRID") {
      if (!frame) r.fail("comes before the FRAM section");
      if (grid) r.fail("a second GRID section");
      grid = true;
      for (std::int64_t& e : tree.frame.extent) {
        const std::uint64_t n = r.get<std::uint64_t>();
        if (n < 1 || n > std::uint64_t(tree.frame.voxelsPerAxis()))
          r.fail("a grid of " + std::to_string(n) + " voxels in a box of " + std::to_string(tree.frame.voxelsPerAxis()));
        e = std::int64_t(n);
      }
    } else if (tag == "NODE") {
      if (!frame) r.fail("comes before the FRAM section");
      if (nodes) r.fail("a second NODE section");
      nodes = true;
      const std::uint64_t count = r.count(kNodeBytes, "node");
      if (count == 0) r.fail("no nodes");
      tree.pointers.resize(count);
      tree.cells.resize(2 * count);
      for (std::size_t n = 0; n < count; ++n) {
        Pointer& p = tree.pointers[n];
        p.parent = r.get<std::int32_t>(), p.left = r.get<std::int32_t>(), p.right = r.get<std::int32_t>(), p.value = r.get<float>();
        tree.cells[2 * n] = r.get<std::uint32_t>(), tree.cells[2 * n + 1] = r.get<std::uint32_t>();
      }
    } else {
      return;
    }
    if (!r.done()) r.fail("trailing bytes");
  });
  if (!frame || !nodes) throw Error(path + ": the tree lacks its " + std::string(frame ? "NODE" : "FRAM") + " section");
  const std::string problem = treeProblem(tree);
  if (!problem.empty()) throw Error(path + ": not a sound tree: " + problem);
  return tree;
}

}  // namespace isoatlas::edit::dvt
