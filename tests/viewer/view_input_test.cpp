// The window driven by real input: mouse and key events sent to the X display it runs on (Xvfb)
// through XTest, as a user's hand would send them, so that they pass through GLFW and Dear ImGui into
// the window's own handlers. Each event is sent at a fixed frame (ViewerOptions::beforeFrame) while
// the script waits, and what it did is read afterwards: masks the script saves, the slice point and
// the status line the window closes with.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>

#include "core/numbers.h"
#include "core/volume_io.h"
#include "tests/multires/mesh_shapes.h"
#include "tests/test_util.h"
#include "tests/viewer/fake_input.h"
#include "tests/viewer/head_phantom.h"
#include "tests/render/test_models.h"
#include "atlas/model_file.h"
#include "edit/dvt/cpu_tree_passes.h"
#include "edit/dvt/dvt_file.h"
#include "edit/dvt/dynamic_volume_tree.h"
#include "edit/solids/rasterise.h"
#include "edit/solids/volume_solid.h"
#include "viewer/viewer_app.h"
#include "render/slice_render.h"

namespace isoatlas::viewer {
namespace {

// Input events keyed by the frame before whose poll they are sent.
using test::FakeInput;
using Timeline = std::map<int, std::function<void(FakeInput&)>>;
std::function<void(int)> play(FakeInput& input, Timeline timeline) {
  return [&input, timeline = std::move(timeline)](int frame) {
    if (const auto it = timeline.find(frame); it != timeline.end()) it->second(input);
  };
}

std::int64_t insideVoxels(const Volume& mask) {
  std::int64_t n = 0;
  for (std::size_t i = 0; i < mask.voxelCount(); ++i) n += mask.value(i) > 0;
  return n;
}

constexpr int kWidth = 640, kHeight = 400;  // slice panels of 100 pixels; the 3D view below them

TEST(ViewWindowInput, MouseAndKeysOnTheSlicesAndTheThreeDView) {
  FakeInput input;
  ASSERT_TRUE(input.open()) << "no X display (the test runs under xvfb-run)";
  ASSERT_TRUE(input.hasXTest());
  const auto dir = test::scratchDir();
  const test::HeadPhantom head = test::headPhantom();
  const std::string volume = (dir / "head.nii.gz").string();
  writeVolume(volume, head.image);
  const auto p = [&](const char* name) { return (dir / name).string(); };
  // Each `frames 30` or `frames 40` is a wait in which the timeline below sends its events; the
  // frame each action runs in is on its right.
  std::ofstream(p("input.txt")) << "seed 0,0,0,9\n"                                  // 0
                                << "frames 30\nsave-mask " << p("undone.nii.gz") << "\n"  // 1, 32
                                << "frames 30\nsave-mask " << p("redone.nii.gz") << "\n"  // 33, 64
                                << "tool brush\nframes 40\nsave-mask " << p("brushed.nii.gz") << "\n"  // 65, 66, 107
                                << "tool navigate\nframes 40\n"                   // 108, 109
                                << "view3d volume\ntool probe\nframes 40\nquit\n";  // 150, 151, 152, 193
  const int n = slicePanelSize(kWidth, kHeight);
  ASSERT_EQ(n, 100);
  auto click = [](int x, int y) {
    return [x, y](FakeInput& in) { in.moveTo(x, y), in.button(1, true); };
  };
  const auto release = [](FakeInput& in) { in.button(1, false); };
  Timeline timeline{
      // Ctrl+Z over the 3D view: the seed is undone.
      {10, [](FakeInput& in) { in.moveTo(150, 250), in.key(FakeInput::Key::Control, true); }},
      {11, [](FakeInput& in) { in.key(FakeInput::Key::Z, true); }},
      {13, [](FakeInput& in) { in.key(FakeInput::Key::Z, false); }},
      {14, [](FakeInput& in) { in.key(FakeInput::Key::Control, false); }},
      // Ctrl+Y: redone.
      {40, [](FakeInput& in) { in.key(FakeInput::Key::Control, true); }},
      {41, [](FakeInput& in) { in.key(FakeInput::Key::Y, true); }},
      {43, [](FakeInput& in) { in.key(FakeInput::Key::Y, false); }},
      {44, [](FakeInput& in) { in.key(FakeInput::Key::Control, false); }},
      // The brush (8 mm, carving) dragged across the axial slice from pixel (30, 50) to (70, 50).
      {75, click(30, 50)},
      {90, release},
      // A click on the coronal slice moves the slices there; two notches of the wheel on the axial
      // slice then move it up two voxels.
      {115, click(130, 40)},
      {117, release},
      {122, [](FakeInput& in) { in.moveTo(50, 50); }},
      {124, [](FakeInput& in) { in.button(4, true), in.button(4, false); }},
      {127, [](FakeInput& in) { in.button(4, true), in.button(4, false); }},
      // Ctrl-click in the middle of the 3D view, the volume rendering on show, with the probe tool.
      {165, [](FakeInput& in) { in.moveTo(150, 250), in.key(FakeInput::Key::Control, true); }},
      {170, click(150, 250)},
      {172, release},
      {173, [](FakeInput& in) { in.key(FakeInput::Key::Control, false); }},
  };
  for (int f = 77; f <= 88; ++f) timeline[f] = [x = 30 + 4 * (f - 77)](FakeInput& in) { in.moveTo(x, 50); };
  ViewerOptions options{.files = {volume}, .script = p("input.txt"), .width = kWidth, .height = kHeight, .backend = "cpu"};
  options.beforeFrame = play(input, timeline);
  const ViewerReport report = runViewer(options);

  const Volume undone = readVolume(p("undone.nii.gz")), redone = readVolume(p("redone.nii.gz")), brushed = readVolume(p("brushed.nii.gz"));
  EXPECT_EQ(insideVoxels(undone), 0) << "Ctrl+Z undid the seed";
  EXPECT_GT(insideVoxels(redone), 500) << "Ctrl+Y seeded again";
  // The drag carved the ball along its path and nowhere else.
  const render::SliceLayout layout(head.image, render::volumeCentre(head.image), n);
  const Vec3 from = layout.world(0, 30, 50), to = layout.world(0, 70, 50);
  std::int64_t carved = 0;
  bool middleCarved = false;
  for (std::int64_t z = 0; z < redone.dims[2]; ++z)
    for (std::int64_t y = 0; y < redone.dims[1]; ++y)
      for (std::int64_t x = 0; x < redone.dims[0]; ++x) {
        const auto i = redone.index(x, y, z);
        if (!(redone.value(i) > 0 && brushed.value(i) == 0)) continue;
        ++carved;
        const Vec3 w = redone.indexToWorld({double(x), double(y), double(z)});
        const double t = std::clamp(dot(w - from, to - from) / dot(to - from, to - from), 0.0, 1.0);
        EXPECT_LT(norm(w - (from + (to - from) * t)), 8 + 1.5 * std::sqrt(3.0)) << "carved away from the stroke at " << w.x << "," << w.y << "," << w.z;
        middleCarved |= norm(w - (from + to) * 0.5) < 3;
      }
  EXPECT_GT(carved, 100);
  EXPECT_TRUE(middleCarved) << "the stroke carved its middle";
  for (std::size_t i = 0; i < redone.voxelCount(); ++i) ASSERT_FALSE(brushed.value(i) > 0 && redone.value(i) == 0) << "the carving brush added";
  // The click on the coronal slice set x and z; the wheel then moved z two voxels up.
  const Vec3 clicked = layout.world(1, 30, 40);
  EXPECT_NEAR(report.slicePoint.x, clicked.x, 1e-9);
  EXPECT_NEAR(report.slicePoint.y, render::volumeCentre(head.image).y, 1e-9);
  EXPECT_NEAR(report.slicePoint.z, clicked.z + 2 * 1.5, 1e-9);
  // The ctrl-click probed a point of the segmentation the 3D view shows.
  ASSERT_EQ(report.status.rfind("probe at ", 0), 0u) << report.status;
  const std::vector<double> at = parseNumbers(report.status.substr(9, report.status.find(':') - 9), "probe", "X,Y,Z");
  ASSERT_EQ(at.size(), 3u);
  EXPECT_LT(norm(Vec3{at[0], at[1], at[2]}), 9 + 1.5 * std::sqrt(3.0)) << report.status;
}

// Ctrl-click on a model stamps the word where the mouse picks the surface.
TEST(ViewWindowInput, CtrlClickOnTheModelStamps) {
  FakeInput input;
  ASSERT_TRUE(input.open()) << "no X display (the test runs under xvfb-run)";
  const auto dir = test::scratchDir();
  const std::string model = (dir / "sphere.isoatlas").string();
  atlas::writeModel(model, test::buildModel(test::sphereMesh(10), 0.05, 9));
  const int viewMiddle = (kWidth - kControlsWidth) / 2;
  ViewerOptions options{.files = {model}, .frames = 30, .width = kWidth, .height = kHeight, .backend = "cpu"};
  options.beforeFrame = play(input, {{5, [&](FakeInput& in) { in.moveTo(viewMiddle, kHeight / 2), in.key(FakeInput::Key::Control, true); }},
                                     {7, [](FakeInput& in) { in.button(1, true); }},
                                     {9, [](FakeInput& in) { in.button(1, false), in.key(FakeInput::Key::Control, false); }}});
  const ViewerReport report = runViewer(options);
  EXPECT_EQ(report.status.rfind("stamped \"isoatlas\" on ", 0), 0u) << report.status;
}

// Ctrl-drag on the tree view paints the tree where the mouse picks it, a dab as it moves, and the
// release ends the stroke: the saved tree is the ball with paint added at its surface only (within
// the brush's radius of the sphere), a latency reported for each dab.
TEST(ViewWindowInput, CtrlDragOnTheTreePaints) {
  FakeInput input;
  ASSERT_TRUE(input.open()) << "no X display (the test runs under xvfb-run)";
  const auto dir = test::scratchDir();
  namespace dvt = edit::dvt;
  const dvt::TreeFrame frame = dvt::frameAround({-1, -1, -1}, {1, 1, 1}, 6);
  dvt::DynamicVolumeTree ball(dvt::VolumeTree::empty(frame), dvt::makeCpuTreePasses());
  ball.write(dvt::rasterise(*dvt::parseBrush("sphere:0,0,0,0.5"), frame, frame.voxelDepth()), dvt::Op::Union);
  ball.collapse();
  const std::string tree = (dir / "ball.dvt").string(), painted = (dir / "painted.dvt").string(), script = (dir / "paint.txt").string();
  dvt::writeDvt(tree, ball.tree());
  std::ofstream(script) << "frames 25\nsave-tree " << painted << "\nquit\n";
  const int viewMiddle = (kWidth - kControlsWidth) / 2;
  ViewerOptions options{.files = {tree}, .script = script, .width = kWidth, .height = kHeight, .backend = "cpu"};
  options.beforeFrame = play(input, {{5, [&](FakeInput& in) { in.moveTo(viewMiddle, kHeight / 2), in.key(FakeInput::Key::Control, true); }},
                                     {7, [](FakeInput& in) { in.button(1, true); }},
                                     {9, [&](FakeInput& in) { in.moveTo(viewMiddle + 20, kHeight / 2); }},
                                     {11, [&](FakeInput& in) { in.moveTo(viewMiddle + 40, kHeight / 2); }},
                                     {13, [](FakeInput& in) { in.button(1, false), in.key(FakeInput::Key::Control, false); }}});
  const ViewerReport report = runViewer(options);
  EXPECT_GE(report.treeDabMs.size(), 2u) << "a dab at the press and as the mouse moved";
  const Volume before = dvt::sampleMask(ball.tree()), after = dvt::sampleMask(dvt::readDvt(painted));
  const double radius = 4 * frame.spacing.x;  // the window's brush: 4 voxels
  std::int64_t added = 0, stray = 0;
  for (std::int64_t k = 0; k < after.dims[2]; ++k)
    for (std::int64_t j = 0; j < after.dims[1]; ++j)
      for (std::int64_t i = 0; i < after.dims[0]; ++i) {
        EXPECT_FALSE(before.at(i, j, k) > 0 && !(after.at(i, j, k) > 0)) << "a union removes nothing";
        if (before.at(i, j, k) > 0 || !(after.at(i, j, k) > 0)) continue;
        ++added;
        stray += std::abs(norm(after.indexToWorld(Vec3{double(i), double(j), double(k)})) - 0.5) > radius + frame.spacing.x;
      }
  EXPECT_GT(added, 20) << "the drag painted the tree";
  EXPECT_EQ(stray, 0) << "the paint lies at the ball's surface, where the mouse picked it";
}

}  // namespace
}  // namespace isoatlas::viewer
