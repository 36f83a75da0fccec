// The window's segmentation session and its script reader, without a window: probing sets T and eps
// as probeSphere says, seeds and undo, requested steps taken exactly, a brush through the volume
// tree carves the mask; scripts read every action and name the line of a bad one.
#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"
#include "edit/solids/solid.h"
#include "levelset/fill_threads.h"
#include "levelset/probe.h"
#include "tests/test_util.h"
#include "tests/viewer/head_phantom.h"
#include "viewer/brush_edit.h"
#include "viewer/segmentation_session.h"
#include "viewer/view_script.h"

namespace isoatlas::viewer {
namespace {

std::int64_t inside(const Volume& mask) {
  std::int64_t n = 0;
  for (std::size_t v = 0; v < mask.voxelCount(); ++v) n += mask.value(v) > 0;
  return n;
}

TEST(ViewSession, ProbeSeedStepsAndUndo) {
  const test::HeadPhantom head = test::headPhantom();
  SegmentationSession s(head.image, levelset::Backend::Cpu);
  const auto r = s.probe({0, 0, 0}, 4.5);
  const auto expected = levelset::probeSphere(head.image, head.image.worldToIndex({0, 0, 0}), 3);
  EXPECT_FLOAT_EQ(s.params().target, float(expected.mean));
  EXPECT_FLOAT_EQ(s.params().width, float(expected.std));
  EXPECT_NEAR(r.mean, 100, 3);
  EXPECT_THROW(s.probe({500, 0, 0}, 3), Error) << "outside the volume";

  EXPECT_FALSE(s.canUndo());
  s.seed({0, 0, 0}, 6, true);
  const std::int64_t seeded = inside(s.levelSet().mask());
  EXPECT_NEAR(double(seeded), 4.0 / 3 * 3.14159 * 64, 40) << "a ball of 4 voxels' radius";
  s.setParams({.target = 100, .width = 30, .alpha = 0.5});
  s.requestSteps(7);
  int taken = 0;
  while (s.running()) taken += s.advance(0.001);
  EXPECT_EQ(taken, 7);
  EXPECT_EQ(s.iterations(), 7);
  EXPECT_GT(inside(s.levelSet().mask()), seeded) << "T and eps of the brain grow the seed";
  const Volume grown = s.levelSet().mask();
  s.seed({0, 0, 0}, 3, false);
  EXPECT_LT(inside(s.levelSet().mask()), inside(grown));
  s.undo();
  EXPECT_EQ(s.levelSet().mask().data, grown.data);
  EXPECT_TRUE(s.canUndo()) << "the first seed is still there to undo";
}

// The window's level set with the topology preserved steps as the command's (the same mask), keeps
// what it had when switched, and fills threads as segment does.
TEST(ViewSession, APreservedTopologyStepsAsTheLevelSetDoes) {
  const test::HeadPhantom head = test::headPhantom();
  SegmentationSession s(head.image, levelset::Backend::Cpu);
  s.setParams({.target = 100, .width = 30, .alpha = 0.5});
  s.seed({0, 0, 0}, 6, true);
  const Volume seeded = s.levelSet().mask();
  s.setTopology(levelset::Topology::Preserve);
  EXPECT_EQ(s.topology(), levelset::Topology::Preserve);
  EXPECT_EQ(s.levelSet().mask().data, seeded.data) << "the mask is kept across the switch";
  s.requestSteps(12);
  while (s.running()) s.advance(0.001);
  levelset::LevelSet direct(head.image, {.target = 100, .width = 30, .alpha = 0.5}, {.topology = levelset::Topology::Preserve});
  direct.setMask(seeded);
  for (int i = 0; i < 12; ++i) direct.step();
  EXPECT_EQ(s.levelSet().mask().data, direct.mask().data);
  Volume filled = direct.mask();
  EXPECT_EQ(s.fillThreads(), levelset::fillThreads(filled));
  EXPECT_EQ(s.levelSet().mask().data, filled.data);
}

TEST(ViewSession, UndoRestoresTheMaskBeforeTheLastEdit) {
  const test::HeadPhantom head = test::headPhantom();
  SegmentationSession s(head.image, levelset::Backend::Cpu);
  s.seed({0, 0, 0}, 9, true);
  const Volume before = s.levelSet().mask();
  s.seed({3, 0, 0}, 4.5, false);
  EXPECT_LT(inside(s.levelSet().mask()), inside(before));
  s.undo();
  EXPECT_EQ(s.levelSet().mask().data, before.data);
}

// Edits undone in turn back to the empty start, redone in turn, and a new edit drops what was left
// to redo; at most kUndoLevels are kept.
TEST(ViewSession, UndoAndRedoWalkThroughTheEdits) {
  const test::HeadPhantom head = test::headPhantom();
  SegmentationSession s(head.image, levelset::Backend::Cpu);
  std::vector<Volume> masks{s.levelSet().mask()};
  s.seed({0, 0, 0}, 9, true);
  masks.push_back(s.levelSet().mask());
  s.seed({3, 0, 0}, 4.5, false);
  masks.push_back(s.levelSet().mask());
  s.seed({-12, 6, 3}, 6, true);
  masks.push_back(s.levelSet().mask());
  for (std::size_t i = 1; i < masks.size(); ++i) EXPECT_NE(masks[i].data, masks[i - 1].data);
  for (int i = 2; i >= 0; --i) {
    ASSERT_TRUE(s.canUndo());
    s.undo();
    EXPECT_EQ(s.levelSet().mask().data, masks[std::size_t(i)].data) << "undo to " << i;
  }
  EXPECT_FALSE(s.canUndo());
  EXPECT_EQ(inside(s.levelSet().mask()), 0);
  for (std::size_t i = 1; i <= 2; ++i) {
    ASSERT_TRUE(s.canRedo());
    s.redo();
    EXPECT_EQ(s.levelSet().mask().data, masks[i].data) << "redo to " << i;
  }
  s.seed({9, -9, 0}, 4.5, true);
  EXPECT_FALSE(s.canRedo()) << "a new edit drops the redo";
  s.undo();
  EXPECT_EQ(s.levelSet().mask().data, masks[2].data);
  for (std::size_t i = 0; i < SegmentationSession::kUndoLevels + 5; ++i) s.seed({double(i % 7), 0, 0}, 3, i % 2 == 0);
  std::size_t undone = 0;
  for (; s.canUndo(); ++undone) s.undo();
  EXPECT_EQ(undone, SegmentationSession::kUndoLevels);
}

TEST(ViewSession, ABrushCarvesThroughTheVolumeTree) {
  const test::HeadPhantom head = test::headPhantom();
  SegmentationSession s(head.image, levelset::Backend::Cpu);
  s.seed({0, 0, 0}, 15, true);
  const Volume before = s.levelSet().mask();
  const auto brush = edit::dvt::parseBrush("sphere:9,0,0,6");
  const BrushResult r = brushSegmentation(s.levelSet(), *brush, edit::dvt::Op::Subtract, levelset::Backend::Cpu);
  std::int64_t carved = 0, leftInBrush = 0, changedElsewhere = 0;
  for (std::int64_t k = 0; k < before.dims[2]; ++k)
    for (std::int64_t j = 0; j < before.dims[1]; ++j)
      for (std::int64_t i = 0; i < before.dims[0]; ++i) {
        const Vec3 w = head.image.indexToWorld({double(i), double(j), double(k)});
        const bool inBrush = norm(w - Vec3{9, 0, 0}) < 6;
        const std::size_t n = before.index(i, j, k);
        if (inBrush) {
          carved += before.value(n) > 0;
          leftInBrush += r.mask.value(n) != 0;
        } else {
          changedElsewhere += r.mask.value(n) != before.value(n);
        }
      }
  EXPECT_GT(carved, 100);
  EXPECT_EQ(leftInBrush, 0);
  EXPECT_EQ(changedElsewhere, 0) << "the tree holds the segmentation voxel for voxel";
  s.replaceMask(r.mask);
  EXPECT_EQ(s.levelSet().mask().data, r.mask.data);
  s.undo();
  EXPECT_EQ(s.levelSet().mask().data, before.data);
}

// A dragged brush: one tree, a write a dab, each dab a capsule from the last; what the slices showed
// while painting is the mask the stroke leaves, which is the segmentation with the swept spheres
// added (then carved), voxel for voxel.
TEST(ViewSession, AStrokeSweepsItsBrushThroughTheDabs) {
  const test::HeadPhantom head = test::headPhantom();
  SegmentationSession s(head.image, levelset::Backend::Cpu);
  s.seed({0, 0, 0}, 12, true);
  const Volume before = s.levelSet().mask();
  const std::vector<Vec3> path{{-16.1, -20.3, 4.2}, {-3.9, -8.2, 4.6}, {14.3, 1.1, 3.8}, {15.2, 17.9, -6.3}};
  for (const bool add : {true, false}) {
    SCOPED_TRACE(add ? "union" : "subtract");
    const double radius = add ? 3.1 : 5.2;
    BrushStroke stroke(s.levelSet(), add ? edit::dvt::Op::Union : edit::dvt::Op::Subtract, levelset::Backend::Cpu);
    for (const Vec3& p : path) stroke.dabTo(p, radius);
    EXPECT_EQ(stroke.dabs(), path.size());
    const Volume preview = stroke.preview();
    const BrushResult r = stroke.finish();
    EXPECT_TRUE(r.mask.data == preview.data) << "the preview is the stroke's mask";
    EXPECT_THROW(stroke.dabTo(path[0], radius), Error) << "a finished stroke takes no more dabs";
    std::int64_t wrong = 0, swept = 0;
    for (std::int64_t k = 0; k < before.dims[2]; ++k)
      for (std::int64_t j = 0; j < before.dims[1]; ++j)
        for (std::int64_t i = 0; i < before.dims[0]; ++i) {
          const Vec3 w = head.image.indexToWorld({double(i), double(j), double(k)});
          const bool inStroke = test::inStroke(w, path, radius);
          const bool was = before.value(before.index(i, j, k)) > 0;
          swept += inStroke && was != add;
          wrong += (r.mask.value(r.mask.index(i, j, k)) > 0) != (add ? was || inStroke : was && !inStroke);
        }
    EXPECT_GT(swept, 100) << "the stroke changes the segmentation";
    EXPECT_EQ(wrong, 0);
  }
}

// A 2D stroke: the same sweep, kept to the layer of voxels of the slice through the first point.
TEST(ViewSession, AStrokeKeptToASliceChangesThatLayerOnly) {
  const test::HeadPhantom head = test::headPhantom();
  SegmentationSession s(head.image, levelset::Backend::Cpu);
  s.seed({0, 0, 0}, 12, true);
  const Volume before = s.levelSet().mask();
  const std::vector<Vec3> path{{-16.1, -20.3, 4.9}, {-3.9, -8.2, 4.9}, {14.3, 1.1, 4.9}};
  for (const int axis : {2, 0}) {
    SCOPED_TRACE(axis);
    BrushStroke stroke(s.levelSet(), edit::dvt::Op::Union, levelset::Backend::Cpu);
    stroke.keepToSlice(axis, path[0]);
    for (const Vec3& p : path) stroke.dabTo(p, 6.2);
    const Volume preview = stroke.preview();
    const BrushResult r = stroke.finish();
    EXPECT_TRUE(r.mask.data == preview.data);
    const std::int64_t layer = std::lround(head.image.worldToIndex(path[0])[axis]);
    std::int64_t wrong = 0, painted = 0;
    for (std::int64_t k = 0; k < before.dims[2]; ++k)
      for (std::int64_t j = 0; j < before.dims[1]; ++j)
        for (std::int64_t i = 0; i < before.dims[0]; ++i) {
          const std::int64_t ijk[3] = {i, j, k};
          const Vec3 w = head.image.indexToWorld({double(i), double(j), double(k)});
          const bool was = before.value(before.index(i, j, k)) > 0;
          const bool paintedHere = ijk[axis] == layer && test::inStroke(w, path, 6.2);
          painted += paintedHere && !was;
          wrong += (r.mask.value(r.mask.index(i, j, k)) > 0) != (was || paintedHere);
        }
    EXPECT_GT(painted, 30) << "the stroke paints its slice";
    EXPECT_EQ(wrong, 0) << "and nothing else";
  }
}

std::string writeScript(const std::filesystem::path& dir, const std::string& text) {
  const auto path = (dir / "actions.txt").string();
  std::ofstream(path) << text;
  return path;
}

TEST(ViewScript, ReadsEveryActionAndNamesTheLineOfABadOne) {
  const auto dir = test::scratchDir();
  const auto actions = readViewScript(writeScript(dir,
                                                  "# a session\n"
                                                  "open head.nii.gz\n"
                                                  "probe 0,0,0   # radius 3 by default\n"
                                                  "seed 0,0,0,6\nunseed 1,2,3,4\nset eps 30\nrun 50\nundo\nredo\n"
                                                  "brush subtract sphere:9,0,0,6\nstroke union 2.5 1,2,3 4,5,6\npaint subtract 3 k 1,2,3\nbuild\nlevels 2 1\nwireframe on\n"
                                                  "render cubes\nmode mesh\nslice 1,2,3\nview3d volume\nclip -y\nstamp 1,2,3,4,0.5 word\nload-mask m.nii.gz\nsave-mask m.nii.gz\n"
                                                  "save-model m.isoatlas\nscreenshot s.png\nframes 3\ntool unseed\nquit\n"));
  ASSERT_EQ(actions.size(), 27u);
  EXPECT_EQ(actions[25].word, "unseed");
  EXPECT_EQ(actions[0].verb, "open");
  EXPECT_EQ(actions[0].line, 2);
  EXPECT_EQ(actions[1].numbers, (std::vector<double>{0, 0, 0, 3}));
  EXPECT_EQ(actions[3].verb, "unseed");
  EXPECT_EQ(actions[4].word, "eps");
  EXPECT_EQ(actions[7].verb, "redo");
  EXPECT_EQ(actions[8].word, "sphere:9,0,0,6");
  EXPECT_FALSE(actions[8].on);
  EXPECT_EQ(actions[9].verb, "stroke");
  EXPECT_TRUE(actions[9].on);
  EXPECT_EQ(actions[9].numbers, (std::vector<double>{2.5, 1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(actions[10].verb, "paint");
  EXPECT_FALSE(actions[10].on);
  EXPECT_EQ(actions[10].word, "k");
  EXPECT_EQ(actions[10].numbers, (std::vector<double>{3, 1, 2, 3}));
  EXPECT_EQ(actions[12].numbers, (std::vector<double>{2, 1}));
  EXPECT_EQ(actions[20].verb, "load-mask");
  EXPECT_EQ(actions[20].word, "m.nii.gz");
  for (const std::string bad : {"probe 0,0", "seed 0,0,0", "seed 0,0,0,-1", "set T 3", "run -2", "run 2.5", "brush union sphere:1,2",
                                "brush add sphere:0,0,0,1", "screenshot s.jpg", "levels 2", "mode volume", "teleport 1,2,3",
                                "open", "quit now", "clip y", "view3d slices", "stamp 1,2,3,4 word", "stamp 1,2,3,4,0 word",
                                "stroke union 2", "stroke carve 2 1,2,3", "redo now", "paint union 2 1,2,3", "paint union 2 z 1,2,3", "stroke union 0 1,2,3", "stroke subtract 2 1,2",
                                "run 6e119", "frames 1000001", "levels 2 1e300", "tool hammer", "tool", "tool brush 8", "load-mask",
                                "load-mask a.nii b.nii"}) {  // the view-script fuzzer's find: no cast of a huge count
    SCOPED_TRACE(bad);
    const Error e = test::thrownError([&] { readViewScript(writeScript(dir, "frames 1\n\n" + bad + "\n")); }, bad);
    EXPECT_NE(std::string(e.what()).find("actions.txt:3:"), std::string::npos) << e.what();
  }
  EXPECT_THROW(readViewScript((dir / "missing.txt").string()), Error);
}

}  // namespace
}  // namespace isoatlas::viewer
