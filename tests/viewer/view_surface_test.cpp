// The window's 3D view of the surface on both solvers: on the GPU the surface is marched where phi
// lies and drawn from the buffers it is left in (extract::GpuMarchingCubes, render::GpuMeshView), on
// the CPU extracted on the host and drawn from there. The same segmentation gives the same picture
// but for shading (the GPU's normals are the field's gradient, the host's the faces').
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <string>

#include "core/image.h"
#include "core/volume_io.h"
#include "tests/test_util.h"
#include "tests/viewer/head_phantom.h"
#include "viewer/viewer_app.h"

namespace isoatlas::viewer {
namespace {

TEST(ViewWindow, TheSurfaceViewIsTheSameOnTheGpuAsOnTheCpu) {
  const auto dir = test::scratchDir();
  const test::HeadPhantom head = test::headPhantom();
  const std::string volume = (dir / "head.nii.gz").string();
  writeVolume(volume, head.image);
  const int width = 880, height = 520;
  Image shots[2];
  for (int gpu = 0; gpu < 2; ++gpu) {
    const std::string script = (dir / "surface.txt").string(), shot = (dir / ("surface" + std::to_string(gpu) + ".png")).string();
    std::ofstream(script) << "open " << volume << "\nseed 0,0,0,6\nset eps 30\nrun 30\nview3d surface\nscreenshot " << shot << "\nquit\n";
    const ViewerReport report = runViewer({.script = script, .width = width, .height = height, .backend = gpu ? "gpu" : "cpu"});
    EXPECT_EQ(report.iterations, 30);
    shots[gpu] = readPng(shot);
  }
  // The 3D view: below the slices, left of the controls.
  const int top = slicePanelSize(width, height);
  std::int64_t covered = 0, differs = 0;
  for (int y = top; y < height; ++y)
    for (int x = 0; x < width - kControlsWidth; ++x) {
      const std::uint8_t *a = shots[0].at(x, y), *b = shots[1].at(x, y);
      const bool onA = !(a[0] == 255 && a[1] == 255 && a[2] == 255), onB = !(b[0] == 255 && b[1] == 255 && b[2] == 255);
      covered += onA;
      differs += onA != onB;
    }
  EXPECT_GT(covered, 2000) << "the surface is in the view";
  EXPECT_LT(double(differs), 0.01 * double(covered)) << "the same silhouette on both solvers";
}

}  // namespace
}  // namespace isoatlas::viewer
