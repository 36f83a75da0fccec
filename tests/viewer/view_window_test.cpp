// isoatlas view in a real window (Xvfb): a model, a volume tree and a volume, each drawn a few frames
// and saved; the pictures show what was loaded where it should be.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <atomic>
#include <functional>
#include <map>
#include <fstream>
#include <thread>

#include "core/error.h"
#include "core/image.h"
#include "core/volume_io.h"
#include "edit/dvt/cpu_tree_passes.h"
#include "edit/dvt/dvt_file.h"
#include "edit/dvt/dynamic_volume_tree.h"
#include "edit/solids/rasterise.h"
#include "edit/solids/volume_solid.h"
#include "tests/multires/mesh_shapes.h"
#include "tests/test_util.h"
#include "tests/viewer/head_phantom.h"
#include "tests/render/test_models.h"
#include "render/orbit.h"
#include "render/scene.h"
#include "render/slice_render.h"
#include "atlas/model_file.h"
#include "core/gl/context.h"
#include "core/gl/resources.h"
#include "core/progress.h"
#include "viewer/model_job.h"
#include "viewer/tree_painting.h"
#include "viewer/viewer_app.h"

namespace isoatlas::viewer {
namespace {

// Pixels of the view area's middle third (left of the controls) that differ from the white background.
double coveredMiddle(const Image& image) {
  const int viewWidth = image.width - kControlsWidth;
  std::int64_t n = 0, all = 0;
  for (int y = image.height / 3; y < 2 * image.height / 3; ++y)
    for (int x = viewWidth / 3; x < 2 * viewWidth / 3; ++x, ++all) n += image.at(x, y)[0] < 240 || image.at(x, y)[2] < 240;
  return double(n) / double(all);
}

Image shoot(const std::string& file, const std::filesystem::path& dir) {
  const std::string png = (dir / (std::filesystem::path(file).filename().string() + ".png")).string();
  runViewer({.files = {file}, .frames = 3, .screenshot = png, .width = 800, .height = 480, .backend = "cpu"});
  return readPng(png);
}

TEST(ViewWindow, ShowsAModelATreeAndAVolume) {
  const auto dir = test::scratchDir();
  const std::string model = (dir / "torus.isoatlas").string(), tree = (dir / "ball.dvt").string(), volume = (dir / "ramp.nii.gz").string();
  atlas::writeModel(model, test::buildModel(test::torusMesh(48, 24), 0.04, 17));
  const edit::dvt::TreeFrame frame = edit::dvt::frameAround({-1, -1, -1}, {1, 1, 1}, 5);
  edit::dvt::DynamicVolumeTree t(edit::dvt::VolumeTree::empty(frame), edit::dvt::makeCpuTreePasses());
  t.write(edit::dvt::rasterise(*edit::dvt::parseBrush("sphere:0,0,0,0.8"), frame, 15), edit::dvt::Op::Union);
  edit::dvt::writeDvt(tree, t.tree());
  writeVolume(volume, test::rampVolume(ScalarType::UInt8, {30, 20, 10}));

  const Image m = shoot(model, dir), b = shoot(tree, dir), v = shoot(volume, dir);
  EXPECT_EQ(m.width, 800);
  EXPECT_GT(coveredMiddle(m), 0.2) << "the torus fills the middle of the window";
  EXPECT_GT(coveredMiddle(b), 0.5) << "the ball fills the middle of the window";
  const int n = slicePanelSize(v.width, v.height);
  std::int64_t slicePixels = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < 3 * n; ++x) slicePixels += v.at(x, y)[0] != 255 || v.at(x, y)[1] != 255;
  EXPECT_GT(double(slicePixels) / (3.0 * n * n), 0.5) << "the slices are shown across the top";
  EXPECT_THROW(runViewer({.files = {model}, .frames = 1, .screenshot = "x.jpg"}), Error);
}

}  // namespace
}  // namespace isoatlas::viewer

namespace isoatlas::viewer {
namespace {

// The window's view area: everything left of the controls.
bool isBackground(const std::uint8_t* p) { return p[0] > 245 && p[1] > 245 && p[2] > 245; }

namespace dvt = edit::dvt;

// A ball of radius 0.5 in a 64^3 tree over [-1, 1]^3, as `isoatlas edit` would save one.
std::string ballTree(const std::filesystem::path& dir) {
  const dvt::TreeFrame frame = dvt::frameAround({-1, -1, -1}, {1, 1, 1}, 6);
  dvt::DynamicVolumeTree t(dvt::VolumeTree::empty(frame), dvt::makeCpuTreePasses());
  t.write(dvt::rasterise(*dvt::parseBrush("sphere:0,0,0,0.5"), frame, frame.voxelDepth()), dvt::Op::Union);
  t.collapse();
  const std::string path = (dir / "ball.dvt").string();
  dvt::writeDvt(path, t.tree());
  return path;
}

// Voxel centres of the tree's grid whose inside-ness differs from `inside`, among those more than
// `margin` (world units) from its boundary (`distance`: signed, > 0 inside).
std::int64_t wrongVoxels(const dvt::VolumeTree& tree, const std::function<double(const Vec3&)>& distance, double margin) {
  const Volume mask = dvt::sampleMask(tree);
  std::int64_t wrong = 0;
  for (std::int64_t k = 0; k < mask.dims[2]; ++k)
    for (std::int64_t j = 0; j < mask.dims[1]; ++j)
      for (std::int64_t i = 0; i < mask.dims[0]; ++i) {
        const double d = distance(mask.indexToWorld(Vec3{double(i), double(j), double(k)}));
        if (std::abs(d) > margin) wrong += (d > 0) != (mask.at(i, j, k) > 0);
      }
  return wrong;
}

double segmentDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp(dot(p - a, ab) / dot(ab, ab), 0.0, 1.0);
  return norm(p - (a + ab * t));
}

// A dab past the node limit throws, and the tree it leaves (changed where it needed no new nodes) is
// what the picture is drawn from: on both backends the buffers the renderer reads hold the painting's
// tree, node for node, not the streams of the dab before.
TEST(TreePainting, ADabPastTheNodeLimitLeavesTheBuffersAsTheTree) {
  const auto context = gl::Context::headless();
  const dvt::VolumeTree ball = dvt::readDvt(ballTree(test::scratchDir()));
  for (const levelset::Backend backend : {levelset::Backend::Cpu, levelset::Backend::Gpu}) {
    viewer::TreePainting painting(ball, backend, {.nodeLimit = ball.nodeCount() + 64});
    EXPECT_THROW(painting.dabTo({0.6, 0.1, 0.2}, 0.3, true), Error) << "a dab needing more nodes than the limit";
    const dvt::VolumeTree now = painting.tree();
    ASSERT_NE(now.pointers, ball.pointers) << "the dab changed the tree where it needed no new nodes";
    const dvt::GpuTreeBuffers buffers = painting.buffers();
    std::vector<dvt::Pointer> pointers(now.pointers.size());
    std::vector<std::uint32_t> cells(now.cells.size());
    glGetNamedBufferSubData(buffers.pointers, 0, GLsizeiptr(pointers.size() * sizeof(dvt::Pointer)), pointers.data());
    glGetNamedBufferSubData(buffers.cells, 0, GLsizeiptr(cells.size() * sizeof(std::uint32_t)), cells.data());
    const char* name = backend == levelset::Backend::Cpu ? "cpu" : "gpu";
    EXPECT_EQ(painting.nodeCount(), now.nodeCount()) << name;
    EXPECT_TRUE(pointers == now.pointers && cells == now.cells) << name << ": the buffers are not the tree the dab left";
  }
}

// A script's stroke in tree mode paints the tree on show, a dab a frame, each drawn before the next:
// the painted tree is the ball with the stroke's capsules added, then carved (truth: the shapes'
// distances, away from their boundaries); the GPU twin (on llvmpipe) paints the same tree node for
// node; the ray-cast picture shows the paint; each dab's latency is reported.
TEST(ViewWindow, PaintsATreeADabAFrame) {
  const auto dir = test::scratchDir();
  const std::string ball = ballTree(dir);
  const auto p = [&](const std::string& name) { return (dir / name).string(); };
  std::map<std::string, dvt::VolumeTree> painted;
  for (const std::string backend : {"cpu", "gpu"}) {
    const std::string script = p("paint_" + backend + ".txt");
    std::ofstream(script) << "render raycast\nscreenshot " << p("before_" + backend + ".png") << "\n"
                          << "stroke union 0.2 0.4,0,0 0.65,0,0 0.9,0,0\nscreenshot " << p("after_" + backend + ".png") << "\n"
                          << "save-tree " << p("added_" + backend + ".dvt") << "\n"
                          << "stroke subtract 0.15 0,0,0.7 0,0,0\nsave-tree " << p("carved_" + backend + ".dvt") << "\nquit\n";
    const ViewerReport report = runViewer({.files = {ball}, .script = script, .width = 640, .height = 400, .backend = backend});
    ASSERT_EQ(report.treeDabMs.size(), 5u) << "one latency a dab";
    std::vector<double> ms = report.treeDabMs;
    std::sort(ms.begin(), ms.end());
    std::printf("tree dabs on the %s backend (64^3, llvmpipe): median %.1f ms, longest %.1f ms from a dab's write to its picture\n",
                backend.c_str(), ms[2], ms[4]);
    EXPECT_GT(ms[0], 0);

    const auto added = [](const Vec3& x) {
      return std::max(0.5 - norm(x), 0.2 - segmentDistance(x, {0.4, 0, 0}, {0.9, 0, 0}));
    };
    const auto carved = [&](const Vec3& x) { return std::min(added(x), segmentDistance(x, {0, 0, 0.7}, {0, 0, 0}) - 0.15); };
    const dvt::VolumeTree a = dvt::readDvt(p("added_" + backend + ".dvt")), c = dvt::readDvt(p("carved_" + backend + ".dvt"));
    const double voxel = a.frame.spacing.x;
    EXPECT_EQ(wrongVoxels(a, added, voxel), 0) << "the ball and the stroke's capsules";
    EXPECT_EQ(wrongVoxels(c, carved, voxel), 0) << "carved by the second stroke";
    EXPECT_EQ(dvt::treeProblem(c), "");
    painted[backend] = c;

    // The picture: the union adds pixels to the ball's.
    const Image before = readPng(p("before_" + backend + ".png")), after = readPng(p("after_" + backend + ".png"));
    std::int64_t covered[2] = {0, 0};
    for (int y = 0; y < before.height; ++y)
      for (int x = 0; x < before.width - kControlsWidth; ++x) covered[0] += !isBackground(before.at(x, y)), covered[1] += !isBackground(after.at(x, y));
    EXPECT_GT(covered[1], covered[0] + 100) << "the painted capsules show in the ray cast";
  }
  EXPECT_TRUE(painted["cpu"] == painted["gpu"]) << "the GPU tree passes paint the CPU's tree, node for node";
}


// The script's `open` reads with the command's --volume, as the files given to it: a 4D file of a
// dark volume and then the head, opened as volume 1, is the head (50 steps from a seed fill most of
// the brain); without --volume the open is refused with the count.
TEST(ViewWindow, TheScriptsOpenReadsTheVolumeTheCommandPicked) {
  const auto dir = test::scratchDir();
  const test::HeadPhantom head = test::headPhantom();
  const auto series = dir / "series.nii";
  writeVolume(series.string(), head.image.sameGeometry(head.image.type));  // volume 0: all 0
  std::string bytes = test::readBytes(series);
  const std::int16_t four = 4, two = 2;
  std::memcpy(bytes.data() + 40, &four, 2);  // dim[0]
  std::memcpy(bytes.data() + 48, &two, 2);   // dim[4]
  bytes.append(reinterpret_cast<const char*>(head.image.data.data()), head.image.data.size());
  test::writeBytes(series, bytes);
  const std::string script = (dir / "open.txt").string(), mask = (dir / "mask.nii.gz").string();
  std::ofstream(script) << "open " << series.string() << "\nprobe 0,0,0,4.5\nseed 0,0,0,6\nset eps 30\nrun 50\nsave-mask " << mask << "\nquit\n";
  runViewer({.script = script, .width = 480, .height = 320, .backend = "cpu", .read = {.volume = 1}});
  const Volume m = readVolume(mask);
  std::int64_t both = 0, inMask = 0, inTruth = 0;
  for (std::size_t n = 0; n < m.voxelCount(); ++n) {
    both += m.value(n) > 0 && head.brain.value(n) > 0;
    inMask += m.value(n) > 0, inTruth += head.brain.value(n) > 0;
  }
  EXPECT_GT(2.0 * double(both) / double(inMask + inTruth), 0.8) << "Dice with the brain: volume 1 was not the one opened";
  try {
    runViewer({.script = script, .width = 480, .height = 320, .backend = "cpu"});
    ADD_FAILURE() << "a 4D file opened without --volume";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("holds 2 volumes"), std::string::npos) << e.what();
  }
}

// A scripted session as a user would have it on a head: probe the brain, seed it, widen eps, run
// 50 steps, brush a hole, look at the tree, build the model, change levels; each screenshot is
// checked against what the session did.
TEST(ViewWindow, ReplaysAScriptedSession) {
  const auto dir = test::scratchDir();
  const test::HeadPhantom head = test::headPhantom();
  const std::string volume = (dir / "head.nii.gz").string();
  writeVolume(volume, head.image);
  const auto p = [&](const char* name) { return (dir / name).string(); };
  const std::string script = p("session.txt");
  std::ofstream(script) << "open " << volume << "\nprobe 0,0,0,4.5\nseed 0,0,0,6\nset eps 30\nrun 50\nscreenshot " << p("segment.png") << "\nsave-mask "
                        << p("mask.nii.gz") << "\nview3d volume\nclip +y\nscreenshot " << p("volume.png") << "\nbrush subtract sphere:12,0,0,7.5\nsave-mask " << p("brushed.nii.gz")
                        << "\nstroke union 2.5 -10.3,-7.1,2.2 -2.2,4.3,2.9 6.1,8.8,27.3\nsave-mask " << p("stroked.nii.gz") << "\nundo\nsave-mask "
                        << p("unstroked.nii.gz") << "\nredo\nsave-mask " << p("restroked.nii.gz") << "\nundo\nload-mask " << p("mask.nii.gz")
                        << "\nsave-mask " << p("reloaded.nii.gz") << "\nundo\nmode tree\nscreenshot " << p("tree.png") << "\nmode segment\nbuild\nlevels 2 1\nstamp 0,-27,0,12,1 iso\nscreenshot "
                        << p("mesh.png") << "\nsave-model " << p("model.isoatlas") << "\nquit\n";
  const int width = 880, height = 520;
  const ViewerReport report = runViewer({.script = script, .width = width, .height = height, .backend = "cpu",
                                         .buildModel = [](const Mesh& surface) { return test::buildModel(surface, 0.05, 9); }});
  for (const auto& [mode, f] : report.modes)
    std::printf("frame time, %s: %d frames, mean %.1f ms, max %.1f ms\n", mode.c_str(), f.frames, f.meanMs, f.maxMs);
  EXPECT_EQ(report.iterations, 50);
  EXPECT_EQ(report.modes.count("segment") + report.modes.count("tree") + report.modes.count("mesh"), 3u);

  // The segmentation: 50 steps from the seed fill most of the brain.
  const Volume mask = readVolume(p("mask.nii.gz"));
  std::int64_t both = 0, inMask = 0, inTruth = 0;
  for (std::size_t n = 0; n < mask.voxelCount(); ++n) {
    both += mask.value(n) > 0 && head.brain.value(n) > 0;
    inMask += mask.value(n) > 0, inTruth += head.brain.value(n) > 0;
  }
  EXPECT_GT(2.0 * double(both) / double(inMask + inTruth), 0.8) << "Dice with the brain";

  // The contour on the slices lies where the mask changes: each contour pixel's nearest voxel has
  // inside and outside voxels among its 26 neighbours.
  const Image seg = readPng(p("segment.png"));
  ASSERT_EQ(seg.width, width);
  const int n = slicePanelSize(width, height);
  const render::SliceLayout layout(head.image, render::volumeCentre(head.image), n);
  std::int64_t contour = 0, onBoundary = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < 3 * n; ++x) {
      const std::uint8_t* c = seg.at(x, y);
      if (c[0] != render::kContourColour[0] || c[1] != render::kContourColour[1] || c[2] != render::kContourColour[2]) continue;
      ++contour;
      const Vec3 ijk = head.image.worldToIndex(layout.world(x / n, x % n + 0.5, y + 0.5));
      bool in = false, out = false;
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const auto i = std::lround(ijk.x) + dx, j = std::lround(ijk.y) + dy, k = std::lround(ijk.z) + dz;
            if (i < 0 || j < 0 || k < 0 || i >= mask.dims[0] || j >= mask.dims[1] || k >= mask.dims[2]) continue;
            (mask.at(i, j, k) > 0 ? in : out) = true;
          }
      onBoundary += in && out;
    }
  std::printf("contour pixels %lld, on the boundary %lld\n", (long long)contour, (long long)onBoundary);
  EXPECT_GT(contour, 3 * n / 2) << "a contour in each slice";
  EXPECT_GT(double(onBoundary), 0.97 * double(contour)) << "the contour lies on the mask's boundary";

  // The volume rendering with the front cut away at the slice point: the cut face shows the contour
  // where the plane cuts the segmentation (the brain, about 17 mm wide there).
  const Image volumeView = readPng(p("volume.png"));
  std::int64_t faceContour = 0;
  for (int y = n; y < height; ++y)
    for (int x = 0; x < width - kControlsWidth; ++x) {
      const std::uint8_t* c = volumeView.at(x, y);
      faceContour += c[0] == 255 && c[1] == 224 && c[2] == 0;
    }
  EXPECT_GT(faceContour, 100) << "the contour on the cut face";

  // The brush carved a ball out of the mask and left the rest as it was.
  const Volume brushed = readVolume(p("brushed.nii.gz"));
  std::int64_t carved = 0, leftInBall = 0, changed = 0;
  for (std::int64_t k = 0; k < mask.dims[2]; ++k)
    for (std::int64_t j = 0; j < mask.dims[1]; ++j)
      for (std::int64_t i = 0; i < mask.dims[0]; ++i) {
        const std::size_t v = mask.index(i, j, k);
        const bool inBall = norm(head.image.indexToWorld({double(i), double(j), double(k)}) - Vec3{12, 0, 0}) < 7.5;
        if (inBall) {
          carved += mask.value(v) > 0;
          leftInBall += brushed.value(v) != 0;
        } else {
          changed += brushed.value(v) != mask.value(v);
        }
      }
  EXPECT_GT(carved, 200);
  EXPECT_EQ(leftInBall, 0);
  EXPECT_EQ(changed, 0);

  // The stroke added the brush swept along its points, one undo took the whole stroke back, redo
  // brought it again.
  const Volume stroked = readVolume(p("stroked.nii.gz"));
  const std::vector<Vec3> path{{-10.3, -7.1, 2.2}, {-2.2, 4.3, 2.9}, {6.1, 8.8, 27.3}};
  std::int64_t added = 0, strokeWrong = 0;
  for (std::int64_t k = 0; k < mask.dims[2]; ++k)
    for (std::int64_t j = 0; j < mask.dims[1]; ++j)
      for (std::int64_t i = 0; i < mask.dims[0]; ++i) {
        const Vec3 w = head.image.indexToWorld({double(i), double(j), double(k)});
        const bool swept = test::inStroke(w, path, 2.5);
        const std::size_t v = mask.index(i, j, k);
        added += swept && brushed.value(v) == 0;
        strokeWrong += (stroked.value(v) != 0) != (swept || brushed.value(v) != 0);
      }
  EXPECT_GT(added, 20) << "the stroke reaches outside the segmentation";
  EXPECT_EQ(strokeWrong, 0);
  EXPECT_TRUE(readVolume(p("unstroked.nii.gz")).data == brushed.data) << "undo takes the stroke back";
  EXPECT_TRUE(readVolume(p("restroked.nii.gz")).data == stroked.data) << "redo brings it again";
  EXPECT_TRUE(readVolume(p("reloaded.nii.gz")).data == mask.data) << "load-mask takes the mask as it was saved";

  // The tree view shows the last stroke's tree (the brushed segmentation with the stroke); the mesh
  // view shows the model where it projects.
  const Image tree = readPng(p("tree.png"));
  std::int64_t treeCovered = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width - kControlsWidth; ++x) treeCovered += !isBackground(tree.at(x, y));
  EXPECT_GT(double(treeCovered) / double((width - kControlsWidth) * height), 0.05);

  const atlas::Model model = atlas::readModel(p("model.isoatlas"));
  EXPECT_GT(model.atlas.details.size(), 0u) << "the stamp gave the front of the brain detail charts";
  const Image mesh = readPng(p("mesh.png"));
  auto context = gl::Context::headless();
  const int viewWidth = width - kControlsWidth;
  render::Scene scene({&model});
  render::AtlasRenderer renderer;
  gl::Framebuffer target(viewWidth, height);
  render::drawFrame(scene, renderer, {.mode = render::CpuRefinement::Mode::Level, .level = 2}, {.mode = render::GpuRefinement::Mode::Level, .halvings = 1},
            render::Orbit{}.camera(scene.bounds(), viewWidth, height), {}, target);
  const Image expected = target.readImage();
  std::int64_t inBoth = 0, inEither = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < viewWidth; ++x) {
      const bool a = !isBackground(mesh.at(x, y)), b = !isBackground(expected.at(x, y));
      inBoth += a && b, inEither += a || b;
    }
  ASSERT_GT(inEither, 1000);
  EXPECT_GT(double(inBoth) / double(inEither), 0.97) << "the window draws the model where the headless renderer does";
}

// A small window on the head phantom that replays `actions`, written to the test's folder as `script`.
ViewerOptions headSession(const std::string& script, const std::string& actions) {
  const auto dir = test::scratchDir();
  const std::string volume = (dir / "head.nii.gz").string();
  writeVolume(volume, test::headPhantom().image);
  std::ofstream((dir / script).string()) << actions;
  return {.files = {volume}, .script = (dir / script).string(), .width = 640, .height = 400, .backend = "cpu"};
}

TEST(ViewWindow, AScriptErrorNamesItsLine) {
  const Error e = test::thrownError([] { runViewer(headSession("bad.txt", "seed 0,0,0,6\nprobe 900,0,0\nquit\n")); },
                                     "a probe outside the volume");
  EXPECT_NE(std::string(e.what()).find("bad.txt:2:"), std::string::npos) << e.what();
}

// A build that reports progress every 10 ms for 30 s, unless it is stopped; it counts its updates and
// says whether it ran to the end.
struct SlowBuild {
  std::atomic<int> updates{0};
  std::atomic<bool> ranToTheEnd{false};
  atlas::Model operator()(const Mesh&) {
    Progress progress("slow build", 3000);
    for (int i = 0; i < 3000; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      progress.update(std::uint64_t(i));
      ++updates;
    }
    ranToTheEnd = true;
    return {};
  }
};

TEST(ModelJob, AFailedBuildIsToldWhenTheModelIsTaken) {
  ModelJob job(test::sphereMesh(10), [](const Mesh&) -> atlas::Model { throw Error("no room for the charts"); });
  for (int i = 0; i < 1000 && !job.done(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_TRUE(job.done());
  EXPECT_STREQ(test::thrownError([&] { job.take(); }, "a failed build's model").what(), "no room for the charts");
}

TEST(ModelJob, AJobDroppedMidBuildStopsTheBuildAtItsNextUpdate) {
  SlowBuild build;
  {
    ModelJob job(test::sphereMesh(10), [&](const Mesh& m) { return build(m); });
    while (build.updates < 10) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }  // the window closes
  EXPECT_FALSE(build.ranToTheEnd);
  EXPECT_LT(build.updates, 3000);
  Progress after("after the job", 2);  // the job's observer is gone: updates no longer throw
  EXPECT_NO_THROW(after.update(1));
}

constexpr const char* kSegmentThenBuild = "seed 0,0,0,6\nset eps 30\nrun 20\nbuild\nquit\n";

TEST(ViewWindow, AFailedBuildStopsTheScriptNamingItsLine) {
  ViewerOptions options = headSession("build.txt", kSegmentThenBuild);
  options.buildModel = [](const Mesh&) -> atlas::Model { throw Error("no room for the charts"); };
  const Error e = test::thrownError([&] { runViewer(options); }, "a script whose build failed");
  EXPECT_NE(std::string(e.what()).find("build.txt:4: build: no room for the charts"), std::string::npos) << e.what();
}

TEST(ViewWindow, ClosingTheWindowMidBuildStopsTheBuild) {
  SlowBuild build;
  ViewerOptions options = headSession("build.txt", kSegmentThenBuild);
  options.buildModel = [&](const Mesh& m) { return build(m); };
  options.frames = 150;  // the window closes long before the build's 30 s
  runViewer(options);
  EXPECT_GT(build.updates, 0) << "the build had started";
  EXPECT_FALSE(build.ranToTheEnd);
}

}  // namespace
}  // namespace isoatlas::viewer
