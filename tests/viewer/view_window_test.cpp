// isoatlas view in a real window (Xvfb): a model, a volume tree and a volume, each drawn a few frames
// and saved; the pictures show what was loaded where it should be.
#include <gtest/gtest.h>

#include "core/error.h"
#include "core/image.h"
#include "core/volume_io.h"
#include "levelset/dvt/cpu_tree_passes.h"
#include "levelset/dvt/dvt_file.h"
#include "levelset/dvt/dynamic_volume_tree.h"
#include "levelset/dvt/rasterise.h"
#include "levelset/dvt/volume_solid.h"
#include "tests/multires/mesh_shapes.h"
#include "tests/test_util.h"
#include "tests/viewer/test_models.h"
#include "viewer/app/viewer_app.h"

namespace isoatlas::viewer {
namespace {

// Pixels of the window's middle third that differ from the white background.
double coveredMiddle(const Image& image) {
  std::int64_t n = 0, all = 0;
  for (int y = image.height / 3; y < 2 * image.height / 3; ++y)
    for (int x = image.width / 3; x < 2 * image.width / 3; ++x, ++all) n += image.at(x, y)[0] < 240 || image.at(x, y)[2] < 240;
  return double(n) / double(all);
}

Image shoot(const std::string& file, const std::filesystem::path& dir) {
  const std::string png = (dir / (std::filesystem::path(file).filename().string() + ".png")).string();
  runViewer({.files = {file}, .frames = 3, .screenshot = png, .width = 480, .height = 360});
  return readPng(png);
}

TEST(ViewWindow, ShowsAModelATreeAndAVolume) {
  const auto dir = test::scratchDir();
  const std::string model = (dir / "torus.isoatlas").string(), tree = (dir / "ball.dvt").string(), volume = (dir / "ramp.nii.gz").string();
  atlas::writeModel(model, test::buildModel(test::torusMesh(48, 24), 0.04, 17));
  const levelset::dvt::TreeFrame frame = levelset::dvt::frameAround({-1, -1, -1}, {1, 1, 1}, 5);
  levelset::dvt::DynamicVolumeTree t(levelset::dvt::VolumeTree::empty(frame), levelset::dvt::makeCpuTreePasses());
  t.write(levelset::dvt::rasterise(*levelset::dvt::parseBrush("sphere:0,0,0,0.8"), frame, 15), levelset::dvt::Op::Union);
  levelset::dvt::writeDvt(tree, t.tree());
  writeVolume(volume, test::rampVolume(ScalarType::UInt8, {30, 20, 10}));

  const Image m = shoot(model, dir), b = shoot(tree, dir), v = shoot(volume, dir);
  EXPECT_EQ(m.width, 480);
  EXPECT_GT(coveredMiddle(m), 0.2) << "the torus fills the middle of the window";
  EXPECT_GT(coveredMiddle(b), 0.5) << "the ball fills the middle of the window";
  EXPECT_GT(coveredMiddle(v), 0.05) << "the slices are shown";
  EXPECT_THROW(runViewer({.files = {model}, .frames = 1, .screenshot = "x.jpg"}), Error);
}

}  // namespace
}  // namespace isoatlas::viewer
