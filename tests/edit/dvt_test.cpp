// The dynamic volume tree: writes against a dense voxel reference, collapse, pointers after every
// pass, the node budget, the GPU passes against the CPU's node for node, segmentations in and out.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>

#include "core/error.h"
#include "edit/dvt/cpu_tree_passes.h"
#include "edit/dvt/dvt_file.h"
#include "edit/dvt/dynamic_volume_tree.h"
#include "edit/dvt/gpu_tree_passes.h"
#include "edit/solids/rasterise.h"
#include "edit/solids/volume_solid.h"
#include "levelset/level_set.h"
#include "tests/gl_context.h"
#include "tests/test_util.h"

namespace isoatlas::edit::dvt {
namespace {

// The unit cube as a 32^3 grid (voxel depth 15).
TreeFrame unitFrame() { return frameAround({0, 0, 0}, {1, 1, 1}, 5); }

std::unique_ptr<TreePasses> passesFor(const std::string& backend) {
  if (backend != "gpu") return makeCpuTreePasses();
  test::glContext();  // made current
  return makeGpuTreePasses();
}

// Every cell centre of depth `depth`, inside by the tree vs by `truth`; returns the mismatches.
std::int64_t mismatches(const VolumeTree& tree, std::uint32_t depth, const std::function<bool(const Vec3&)>& truth) {
  std::int64_t bad = 0;
  const std::uint32_t n[3] = {1u << splitsOf(0, depth), 1u << splitsOf(1, depth), 1u << splitsOf(2, depth)};
  for (std::uint32_t z = 0; z < n[2]; ++z)
    for (std::uint32_t y = 0; y < n[1]; ++y)
      for (std::uint32_t x = 0; x < n[0]; ++x) {
        const Cell c{x, y, z, depth};
        const bool inTree = sampleAt(tree, tree.frame.centreIndex(c)).value > 0;
        bad += inTree != truth(tree.frame.centreWorld(c));
      }
  return bad;
}

bool inside(const DistanceSolid& s, const Vec3& p) { return s.signedDistance(p) < 0; }

class Writes : public ::testing::TestWithParam<std::tuple<std::string, bool, std::uint32_t>> {};

TEST_P(Writes, UnionAndSubtractMatchADenseReference) {
  const auto [backend, hierarchical, depth] = GetParam();
  const auto sphere = parseBrush("sphere:0.5,0.5,0.5,0.3");
  const auto box = parseBrush("box:0.45,0.1,0.1,1.2,0.6,0.9");
  const auto capsule = parseBrush("capsule:0.2,0.8,0.5,0.8,0.8,0.5,0.07");
  DynamicVolumeTree tree(VolumeTree::empty(unitFrame()), passesFor(backend));
  tree.write(rasterise(*sphere, unitFrame(), depth, hierarchical), Op::Union);
  EXPECT_EQ(treeProblem(tree.tree()), "");
  EXPECT_EQ(mismatches(tree.tree(), depth, [&](const Vec3& p) { return inside(*sphere, p); }), 0);
  tree.write(rasterise(*box, unitFrame(), depth, hierarchical), Op::Subtract);
  tree.write(rasterise(*capsule, unitFrame(), depth, hierarchical), Op::Union);
  const VolumeTree t = tree.tree();
  EXPECT_EQ(treeProblem(t), "");
  auto truth = [&](const Vec3& p) { return (inside(*sphere, p) && !inside(*box, p)) || inside(*capsule, p); };
  EXPECT_EQ(mismatches(t, depth, truth), 0);
  const std::uint64_t before = tree.nodeCount();
  EXPECT_GT(tree.collapse(), 0u);
  EXPECT_LT(tree.nodeCount(), before);
  EXPECT_EQ(treeProblem(tree.tree()), "");
  EXPECT_EQ(mismatches(tree.tree(), depth, truth), 0) << "collapse changed the volume";
  EXPECT_EQ(tree.collapse(), 0u) << "a second collapse still found equal siblings";
}

INSTANTIATE_TEST_SUITE_P(Dvt, Writes,
                         ::testing::Combine(::testing::Values("cpu", "gpu"), ::testing::Bool(), ::testing::Values(15u, 16u)),
                         [](const auto& info) {
                           return std::get<0>(info.param) + (std::get<1>(info.param) ? "_hierarchical_" : "_flat_") +
                                  std::to_string(std::get<2>(info.param));
                         });

TEST(Dvt, PointersAgreeAfterEveryPass) {
  for (const std::string backend : {"cpu", "gpu"}) {
    auto passes = passesFor(backend);
    VolumeTree start = VolumeTree::empty(unitFrame());
    passes->load(start);
    int iterations = 0;
    // A deep write, then a coarse one that reduces its subtrees, then a subtraction.
    const std::vector<std::pair<std::string, std::pair<Op, std::uint32_t>>> writes = {
        {"torus:0.5,0.5,0.5,0.3,0.1", {Op::Union, 17}}, {"sphere:0.6,0.5,0.5,0.2", {Op::Union, 9}},
        {"box:0.3,0.3,0.3,0.6,0.6,0.6", {Op::Subtract, 16}}};
    for (const auto& [shape, how] : writes) {
      passes->setInput(rasterise(*parseBrush(shape), unitFrame(), how.second).take());
      for (;; ++iterations) {
        passes->mark(how.first);
        const Plan plan = passes->plan(true);
        if (plan.changes == 0) break;
        passes->restructure(plan, true, 1u << 24);
        ASSERT_EQ(treeProblem(passes->download()), "") << backend << ", " << shape << ", pass " << iterations;
      }
      ASSERT_EQ(treeProblem(passes->download()), "") << backend << ", " << shape;
    }
    EXPECT_GE(iterations, 3) << "each write restructures";
    // The collapse's passes: mark equal siblings, restructure without expanding.
    int collapses = 0;
    for (; passes->markCollapse() > 0; ++collapses) {
      passes->restructure(passes->plan(false), false, 1u << 24);
      ASSERT_EQ(treeProblem(passes->download()), "") << backend << ", collapse pass " << collapses;
    }
    EXPECT_GE(collapses, 1) << backend << ": the carved box leaves equal siblings to join";
  }
}

// The CPU cuts the tree into bricks below a top index (16^3 voxels each: 8 bricks for unitFrame's
// 32^3 voxels, 4096 under a 9-level top at 256^3) and ends a write in one restructure; the GPU keeps
// one stream and adds at most kExpandLevels levels a pass. The trees must still be the same.
TEST(Dvt, GpuPassesMakeTheCpuStreamsNodeForNode) {
  for (const int splits : {5, 8}) {
    const TreeFrame frame = frameAround({0, 0, 0}, {1, 1, 1}, splits);
    DynamicVolumeTree cpu(VolumeTree::empty(frame), makeCpuTreePasses(), {.collapseEvery = 3});
    test::glContext();  // made current
    DynamicVolumeTree gpu(VolumeTree::empty(frame), makeGpuTreePasses(), {.collapseEvery = 3});
    for (int step = 0; step < 8; ++step) {
      const double a = 0.4 * step;
      const std::string brush = "sphere:" + std::to_string(0.5 + 0.3 * std::cos(a)) + "," + std::to_string(0.5 + 0.3 * std::sin(a)) + ",0.5,0.08";
      const auto input = rasterise(*parseBrush(brush), frame, std::uint32_t(3 * splits + 1) + step % 3);
      const Op op = step == 5 ? Op::Subtract : Op::Union;
      cpu.write(input, op), gpu.write(input, op);
      const VolumeTree c = cpu.tree(), g = gpu.tree();
      ASSERT_EQ(c.nodeCount(), g.nodeCount()) << splits << " splits, step " << step;
      ASSERT_EQ(c.nodeCount(), cpu.nodeCount());
      ASSERT_TRUE(c.cells == g.cells) << splits << " splits, step " << step;
      for (std::size_t n = 0; n < c.nodeCount(); ++n) ASSERT_EQ(c.pointers[n], g.pointers[n]) << splits << " splits, step " << step << ", node " << n;
      ASSERT_EQ(treeProblem(c), "");
    }
    // Coarse band leaves expanded by finer voxels, where their values saturate on the way down
    // (expansionCut stops there, whatever the levels a pass adds); then a coarse subtraction removes
    // whole subtrees of the top and their bricks.
    const std::vector<std::pair<std::string, std::uint32_t>> writes{{"sphere:0.3,0.5,0.5,0.15", 3 * splits - 3},
                                                                    {"sphere:0.32,0.52,0.5,0.15", 3 * splits + 4}};
    for (const auto& [shape, depth] : writes) cpu.write(rasterise(*parseBrush(shape), frame, depth), Op::Union), gpu.write(rasterise(*parseBrush(shape), frame, depth), Op::Union);
    ASSERT_TRUE(cpu.tree() == gpu.tree()) << splits << " splits: " << cpu.nodeCount() << " and " << gpu.nodeCount() << " nodes";
    cpu.write(rasterise(*parseBrush("box:0,0,0,0.5,1,1"), frame, 6), Op::Subtract);
    gpu.write(rasterise(*parseBrush("box:0,0,0,0.5,1,1"), frame, 6), Op::Subtract);
    cpu.collapse(), gpu.collapse();
    ASSERT_TRUE(cpu.tree() == gpu.tree()) << splits << " splits: " << cpu.nodeCount() << " and " << gpu.nodeCount() << " nodes";
    // And a tree loaded into fresh CPU passes comes back as it went in.
    DynamicVolumeTree reloaded(cpu.tree(), makeCpuTreePasses());
    ASSERT_TRUE(reloaded.tree() == cpu.tree());
  }
}

// A GPU write runs as one chain of passes sized on the GPU (writeChained), reading its state back
// once at the end, and a collapse as a chain read once a batch (collapseChained); the host-driven
// passes read counters between every pass. Same trees, node for node: from an empty tree (its
// streams grow mid-chain: more reads), deep writes under coarse leaves (several restructures in one
// chain), reductions, a subtraction and collapses (every 4 writes, and at the end).
TEST(Dvt, ChainedGpuWritesMakeTheHostDrivenTreesNodeForNode) {
  const TreeFrame frame = frameAround({0, 0, 0}, {1, 1, 1}, 6);
  test::glContext();  // made current
  DynamicVolumeTree chained(VolumeTree::empty(frame), makeGpuTreePasses(), {.collapseEvery = 4});
  DynamicVolumeTree driven(VolumeTree::empty(frame), makeGpuTreePasses(), {.collapseEvery = 4, .chainPasses = false});
  const std::vector<std::tuple<std::string, std::uint32_t, Op>> writes{
      {"sphere:0.5,0.5,0.5,0.3", 9, Op::Union},          {"torus:0.5,0.5,0.5,0.3,0.08", 19, Op::Union},
      {"sphere:0.7,0.5,0.5,0.1", 20, Op::Union},         {"sphere:0.5,0.5,0.5,0.2", 12, Op::Union},
      {"box:0.2,0.2,0.2,0.5,0.6,0.9", 18, Op::Subtract}, {"capsule:0.1,0.1,0.5,0.9,0.9,0.5,0.04", 20, Op::Union},
      {"sphere:0.3,0.6,0.5,0.05", 19, Op::Subtract}};
  int severalRestructures = 0, grew = 0;
  for (std::size_t w = 0; w < writes.size(); ++w) {
    const auto& [shape, depth, op] = writes[w];
    const auto input = rasterise(*parseBrush(shape), frame, depth);
    const std::uint64_t bytesBefore = chained.bytes();
    const WriteStats a = chained.write(input, op), b = driven.write(input, op);
    ASSERT_TRUE(chained.tree() == driven.tree()) << "write " << w << " (" << shape << "): " << chained.nodeCount() << " and "
                                                 << driven.nodeCount() << " nodes";
    ASSERT_EQ(treeProblem(chained.tree()), "") << "write " << w;
    EXPECT_EQ(a.iterations, b.iterations) << "write " << w;
    severalRestructures += a.iterations > 1;
    grew += a.chainReads > 1 && chained.bytes() > bytesBefore;  // stopped for the streams to grow, and went on
  }
  EXPECT_GE(severalRestructures, 2) << "some writes restructure more than once in their chain";
  EXPECT_GE(grew, 1) << "the streams grew in a chain at least once";
  // Once the streams are large enough, a brush stroke's write is read back once.
  const WriteStats dab = chained.write(rasterise(*parseBrush("sphere:0.52,0.5,0.5,0.04"), frame, 19), Op::Union);
  driven.write(rasterise(*parseBrush("sphere:0.52,0.5,0.5,0.04"), frame, 19), Op::Union);
  EXPECT_EQ(dab.chainReads, 1);
  ASSERT_TRUE(chained.tree() == driven.tree());
  // And a collapse as a chain (a level of siblings an iteration, read once a batch) joins what the
  // host-driven one joins, after a box of an eighth of the cube written flat (every voxel 18 levels
  // down): joined up to the box's one cell, 15 levels up, in more than one batch of 8.
  for (DynamicVolumeTree* t : {&chained, &driven}) t->write(rasterise(*parseBrush("box:0.5,0,0,1,0.5,0.5"), frame, 18, false), Op::Union);
  ASSERT_TRUE(chained.tree() == driven.tree());
  const std::uint64_t before = chained.nodeCount();
  const std::optional<ChainRun> collapsed = chained.passes().collapseChained();
  ASSERT_TRUE(collapsed.has_value());
  TreePasses& host = driven.passes();
  int passes = 0;
  for (; host.markCollapse() > 0; ++passes) host.restructure(host.plan(false), false, kDefaultNodeLimit);
  EXPECT_GT(passes, 8) << "a collapse of more levels than a batch";
  EXPECT_EQ(collapsed->iterations, passes);
  EXPECT_EQ(collapsed->reads, passes / 8 + 1) << "a read every 8 iterations, the last one's mark finding nothing";
  EXPECT_GT(before - chained.nodeCount(), 0u);
  ASSERT_TRUE(chained.tree() == host.download());
  EXPECT_EQ(chained.collapse(), 0u);
}

// Past the node limit a chain stops before the restructure that would pass it and hands the write
// to the host-driven passes, which apply what fits and throw: the same tree as theirs alone.
TEST(Dvt, AChainedWritePastTheNodeLimitEndsAsTheHostDrivenOne) {
  test::glContext();
  DynamicVolumeTree chained(VolumeTree::empty(unitFrame()), makeGpuTreePasses(), {.nodeLimit = 2000});
  DynamicVolumeTree driven(VolumeTree::empty(unitFrame()), makeGpuTreePasses(), {.nodeLimit = 2000, .chainPasses = false});
  for (DynamicVolumeTree* t : {&chained, &driven}) {
    t->write(rasterise(*parseBrush("sphere:0.5,0.5,0.5,0.3"), unitFrame(), 9), Op::Union);
    EXPECT_THROW(t->write(rasterise(*parseBrush("torus:0.5,0.5,0.5,0.3,0.05"), unitFrame(), 18), Op::Union), Error);
  }
  ASSERT_TRUE(chained.tree() == driven.tree()) << chained.nodeCount() << " and " << driven.nodeCount() << " nodes";
  EXPECT_LE(chained.nodeCount(), 2000u);
  for (DynamicVolumeTree* t : {&chained, &driven}) t->write(rasterise(*parseBrush("box:0,0,0,0.5,1,1"), unitFrame(), 6), Op::Subtract);
  ASSERT_TRUE(chained.tree() == driven.tree());
}

// Voxels from anywhere are put in pre-order; the rasteriser makes them so (a write trusts it).
TEST(Dvt, InputsComeInPreOrder) {
  const PreOrderInput made = rasterise(*parseBrush("torus:0.5,0.5,0.5,0.3,0.1"), unitFrame(), 16);
  ASSERT_GT(made.size(), 1000u);
  EXPECT_TRUE(inPreOrder(made.voxels()));
  std::vector<InputVoxel> shuffled = made.voxels();
  std::reverse(shuffled.begin(), shuffled.end());
  std::swap(shuffled[7], shuffled[shuffled.size() / 2]);
  EXPECT_FALSE(inPreOrder(shuffled));
  const PreOrderInput sorted(shuffled);
  ASSERT_EQ(sorted.size(), made.size());
  for (std::size_t i = 0; i < made.size(); ++i) {
    EXPECT_EQ(sorted.voxels()[i].xy, made.voxels()[i].xy) << i;
    EXPECT_EQ(sorted.voxels()[i].zd, made.voxels()[i].zd) << i;
    EXPECT_EQ(sorted.voxels()[i].value, made.voxels()[i].value) << i;
  }
}

TEST(Dvt, NodeBudgetGivesAnErrorAndAValidTree) {
  for (const std::string backend : {"cpu", "gpu"}) {
    DynamicVolumeTree tree(VolumeTree::empty(unitFrame()), passesFor(backend), {.nodeLimit = 2000});
    tree.write(rasterise(*parseBrush("sphere:0.5,0.5,0.5,0.3"), unitFrame(), 9), Op::Union);
    EXPECT_THROW(tree.write(rasterise(*parseBrush("torus:0.5,0.5,0.5,0.3,0.05"), unitFrame(), 18), Op::Union), Error);
    EXPECT_LE(tree.nodeCount(), 2000u);
    EXPECT_EQ(treeProblem(tree.tree()), "") << backend;
    // Still usable: a coarse subtraction fits and is applied.
    const auto box = parseBrush("box:0,0,0,0.5,1,1");
    tree.write(rasterise(*box, unitFrame(), 6), Op::Subtract);
    EXPECT_EQ(treeProblem(tree.tree()), "") << backend;
    EXPECT_LT(sampleAt(tree.tree(), tree.frame().centreIndex(Cell{0, 0, 0, 3})).value, 0) << backend;
  }
}

// Pointers are 32-bit signed indices: a larger budget could not be held, and the GPU's plan counts
// in 32 bits (it reports a total past kMaxTreeNodes as over any limit).
TEST(Dvt, ANodeLimitPastWhatPointersIndexIsRefused) {
  EXPECT_THROW(DynamicVolumeTree(VolumeTree::empty(unitFrame()), passesFor("cpu"), {.nodeLimit = kMaxTreeNodes + 1}), Error);
  EXPECT_NO_THROW(DynamicVolumeTree(VolumeTree::empty(unitFrame()), passesFor("cpu"), {.nodeLimit = kMaxTreeNodes}));
}

TEST(Dvt, MaskRoundTripsThroughATree) {
  Volume mask = Volume::zeros({23, 17, 12}, ScalarType::UInt8);
  mask.spacing = {0.8, 1.0, 1.5};
  mask.origin = {-3, 4, 10};
  for (std::int64_t k = 0; k < 12; ++k)
    for (std::int64_t j = 0; j < 17; ++j)
      for (std::int64_t i = 0; i < 23; ++i)
        if ((i - 11) * (i - 11) + (j - 8) * (j - 8) * 2 + (k - 6) * (k - 6) * 3 < 70 && (i + j + k) % 7 != 0)
          mask.setValue(mask.index(i, j, k), 1);
  const TreeFrame frame = frameOf(mask);
  EXPECT_EQ(frame.voxelSplits, 5);
  const VolumeSolid solid(mask);
  DynamicVolumeTree tree(VolumeTree::empty(frame), makeCpuTreePasses());
  tree.write(rasterise(solid, frame, frame.voxelDepth()), Op::Union);
  tree.collapse();
  const Volume back = sampleMask(tree.tree(), mask.dims);
  EXPECT_EQ(back.data, mask.data);
  EXPECT_EQ(back.origin, mask.origin);
  EXPECT_EQ(back.spacing, mask.spacing);
}

TEST(Dvt, FileRoundTripAndDamage) {
  TreeFrame frame = unitFrame();
  frame.direction.m[0] = {0, -1, 0}, frame.direction.m[1] = {1, 0, 0};
  DynamicVolumeTree tree(VolumeTree::empty(frame), makeCpuTreePasses());
  tree.write(rasterise(*parseBrush("torus:0.2,0.5,0.5,0.3,0.1"), frame, 17), Op::Union);
  const auto dir = test::scratchDir();
  const std::string path = (dir / "t.dvt").string();
  writeDvt(path, tree.tree());
  EXPECT_TRUE(readDvt(path) == tree.tree());
  const std::string bytes = test::readBytes(path);
  for (const std::size_t cut : {std::size_t(3), std::size_t(13), std::size_t(40), bytes.size() - 1}) {
    test::writeBytes(dir / "cut.dvt", bytes.substr(0, cut));
    EXPECT_THROW(readDvt((dir / "cut.dvt").string()), Error) << cut;
  }
  // A child pointing elsewhere: the writer refuses it, and so does the reader with the checksum not
  // checked (node 1's left child, after the NODE section's header and count and node 0).
  VolumeTree bad = tree.tree();
  std::swap(bad.pointers[1].left, bad.pointers[1].right);
  EXPECT_NE(treeProblem(bad), "");
  EXPECT_THROW(writeDvt(path, bad), Error);
  std::string swapped = bytes;
  const std::size_t node1 = swapped.find("NODE") + 4 + 8 + 4 + 8 + 24;
  std::swap_ranges(swapped.begin() + std::ptrdiff_t(node1 + 4), swapped.begin() + std::ptrdiff_t(node1 + 8),
                   swapped.begin() + std::ptrdiff_t(node1 + 8));
  test::writeBytes(dir / "swapped.dvt", swapped);
  EXPECT_THROW(readDvt((dir / "swapped.dvt").string()), Error) << "the checksum";
  const Error e = test::thrownError([&] { readDvt((dir / "swapped.dvt").string(), false); }, "a tree with swapped children");
  EXPECT_NE(std::string(e.what()).find("not a sound tree"), std::string::npos) << e.what();
}

// A tree of a volume keeps the volume's grid (GRID section) through the file; a grid larger than
// the box is refused.
TEST(Dvt, FileKeepsTheSourceGrid) {
  Volume mask = Volume::zeros({23, 17, 12}, ScalarType::UInt8);
  mask.setValue(mask.index(5, 6, 7), 1);
  const TreeFrame frame = frameOf(mask);
  DynamicVolumeTree tree(VolumeTree::empty(frame), makeCpuTreePasses());
  tree.write(rasterise(VolumeSolid(mask), frame, frame.voxelDepth()), Op::Union);
  const auto dir = test::scratchDir();
  const std::string path = (dir / "g.dvt").string();
  writeDvt(path, tree.tree());
  const VolumeTree back = readDvt(path);
  EXPECT_EQ(back.frame.grid(), mask.dims);
  EXPECT_EQ(sampleMask(back).data, mask.data);
  std::string bytes = test::readBytes(path);
  const std::size_t grid = bytes.find("GRID") + 4 + 8 + 4;
  bytes[grid] = char(33);  // 33 voxels along x in a box of 32
  test::writeBytes(dir / "wide.dvt", bytes);
  EXPECT_THROW(readDvt((dir / "wide.dvt").string(), false), Error);
}

// The committed tree pins the .dvt format: what it holds, and the writer's bytes for it.
TEST(Dvt, GoldenTreePinsTheFormat) {
  const std::string golden = std::string(ISOATLAS_SOURCE_DIR) + "/tests/edit/fixtures/golden_tree.dvt";
  const VolumeTree tree = readDvt(golden);
  EXPECT_EQ(tree.nodeCount(), 171u);
  EXPECT_EQ(tree.leafCount(), 86u);
  EXPECT_EQ(tree.frame.grid(), (std::array<std::int64_t, 3>{181, 217, 181}));
  const Volume mask = sampleMask(tree);
  EXPECT_EQ(std::count(mask.data.begin(), mask.data.end(), std::byte{1}), 1769472);
  const auto dir = test::scratchDir();
  writeDvt((dir / "t.dvt").string(), tree);
  test::expectGolden(golden, test::readBytes(dir / "t.dvt"));
}

// The rasteriser holds a write's voxels within a budget: the exact count fits, one fewer is refused,
// and a depth whose voxels no budget holds is refused from the coarse levels, at once.
TEST(Dvt, RasteriserKeepsToItsVoxelBudget) {
  for (const char* shape : {"sphere:0.5,0.5,0.5,0.3", "torus:0.5,0.5,0.5,0.3,0.05", "box:0.1,0.2,0.3,0.7,0.8,0.6",
                            "capsule:0.2,0.2,0.2,0.8,0.7,0.6,0.04"}) {
    const auto solid = parseBrush(shape);
    for (const std::uint32_t depth : {15u, 18u, 21u})
      for (const bool hierarchical : {true, false}) {
        const std::uint64_t n = rasterise(*solid, unitFrame(), depth, hierarchical).size();
        EXPECT_EQ(rasterise(*solid, unitFrame(), depth, hierarchical, n).size(), n) << shape << " at " << depth;
        EXPECT_THROW(rasterise(*solid, unitFrame(), depth, hierarchical, n - 1), Error) << shape << " at " << depth;
      }
  }
  const auto sphere = parseBrush("sphere:0.5,0.5,0.5,0.3");
  EXPECT_THROW(checkVoxelBudget(*sphere, frameAround({0, 0, 0}, {1, 1, 1}, 16), 48), Error);
  EXPECT_NO_THROW(checkVoxelBudget(*sphere, unitFrame(), 21));
}

TEST(Dvt, LevelSetPagesMakeTheTreeOfItsMask) {
  Volume source = Volume::zeros({40, 34, 20}, ScalarType::UInt8);
  source.spacing = {1, 1, 1.5};
  for (std::int64_t k = 0; k < 20; ++k)
    for (std::int64_t j = 0; j < 34; ++j)
      for (std::int64_t i = 0; i < 40; ++i)
        source.setValue(source.index(i, j, k), (i - 18) * (i - 18) + (j - 16) * (j - 16) + 4 * (k - 9) * (k - 9) < 140 ? 200 : 40);
  levelset::LevelSet levelSet(source, {200, 60, 0.8f}, {.backend = levelset::Backend::Cpu});
  levelSet.addSphere({18, 16, 9}, 3);
  levelSet.run({.maxIterations = 40});
  const TreeFrame frame = frameOf(levelSet.geometry());
  DynamicVolumeTree tree(VolumeTree::empty(frame), makeCpuTreePasses());
  tree.write(rasterise(VolumeSolid(levelSet), frame, frame.voxelDepth()), Op::Union);
  const Volume mask = levelSet.mask(), back = sampleMask(tree.tree(), mask.dims);
  std::int64_t inside = 0;
  for (std::size_t n = 0; n < mask.voxelCount(); ++n) inside += mask.value(n) > 0;
  EXPECT_GT(inside, 500);
  EXPECT_EQ(back.data, mask.data);
}

// The level set's phi is far steeper than a distance at its front and clamped a few voxels out: a
// crossed leaf still holds the distance to phi's zero set (to first order), so that the field between
// leaves, which the ray caster lights and extract/ meshes, puts the surface where phi does.
TEST(Dvt, ASteepClampedPhiGivesDistancesInTheBand) {
  Volume phi = Volume::zeros({24, 24, 16}, ScalarType::Float32);
  phi.spacing = {1, 1, 1.5};
  const Vec3 centre{11.3, 12.1, 11.6};
  const double radius = 7.2;
  for (std::int64_t k = 0; k < 16; ++k)
    for (std::int64_t j = 0; j < 24; ++j)
      for (std::int64_t i = 0; i < 24; ++i) {
        const double d = radius - norm(Vec3{double(i), double(j), 1.5 * double(k)} - centre);
        phi.setValue(phi.index(i, j, k), std::clamp(4 * d, -3.0, 3.0));
      }
  const TreeFrame frame = frameOf(phi);
  DynamicVolumeTree tree(VolumeTree::empty(frame), makeCpuTreePasses());
  tree.write(rasterise(VolumeSolid(phi), frame, frame.voxelDepth()), Op::Union);
  const VolumeTree& t = tree.tree();
  std::int64_t near = 0;
  double worst = 0;
  for (std::size_t n = 0; n < t.nodeCount(); ++n) {
    if (!t.pointers[n].leaf()) continue;
    const Cell c = t.cell(n);
    const double truth = radius - norm(frame.centreWorld(c) - centre);
    if (std::abs(truth) > 0.6) continue;  // phi itself is unclamped here
    ++near;
    worst = std::max(worst, std::abs(double(t.pointers[n].value) * frame.radius(c.depth) - truth));
  }
  EXPECT_GT(near, 300);
  EXPECT_LT(worst, 0.1);
}

TEST(Dvt, MalformedBrushesAreRefused) {
  for (const char* bad : {"sphere", "sphere:1,2,3", "sphere:1,2,3,0", "sphere:1,2,x,4", "cube:1,2,3,4", "box:0,0,0,1,1,0",
                          "torus:0,0,0,1", "capsule:0,0,0,1,1,1,-1", "sphere:1,2,3,nan", "sphere:1,2,3,4,", ""})
    EXPECT_THROW(parseBrush(bad), Error) << bad;
  EXPECT_THROW(rasterise(*parseBrush("sphere:0,0,0,1"), unitFrame(), kMaxDepth + 1), Error);
}

}  // namespace
}  // namespace isoatlas::edit::dvt
