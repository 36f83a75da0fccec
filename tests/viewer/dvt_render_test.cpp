// Pictures of a dynamic volume tree: the ray caster and the cubes against a sphere's true silhouette
// (no holes inside it, on a small grid and a large one), and a GPU tree's own buffers against its
// streams uploaded.
#include <gtest/gtest.h>

#include <numbers>

#include "levelset/dvt/cpu_tree_passes.h"
#include "levelset/dvt/dynamic_volume_tree.h"
#include "levelset/dvt/gpu_tree_passes.h"
#include "levelset/dvt/rasterise.h"
#include "levelset/dvt/volume_solid.h"
#include "tests/gl_context.h"
#include "tests/viewer/silhouette.h"
#include "viewer/dvt_render.h"

namespace isoatlas::viewer {
namespace {
namespace dvt = levelset::dvt;

TEST(DvtRender, SilhouettesOfASphereAndTheGpuTreesOwnBuffers) {
  gl::Context& context = test::glContext();
  const dvt::TreeFrame frame = dvt::frameAround({-1, -1, -1}, {1, 1, 1}, 5);
  dvt::DynamicVolumeTree tree(dvt::VolumeTree::empty(frame), dvt::makeGpuTreePasses(context));
  tree.write(dvt::rasterise(*dvt::parseBrush("sphere:0,0,0,0.8"), frame, 16), dvt::Op::Union);
  const dvt::VolumeTree streams = tree.tree();
  DvtView view{.camera = Camera::framing(insideBounds(streams), 160, 120, {0.3, 1, -0.2})};
  const Image rays = renderTree(streams, view);
  // Voxels of ~1.5-3 pixels here: the rays miss the outline by about a pixel (a grazing ray passes leaves
  // whose centres are outside), the cubes by their steps.
  const auto [rayWrong, disc] = test::silhouetteMismatch(rays, view.camera, {0, 0, 0}, 0.8);
  const double outline = 2 * std::sqrt(std::numbers::pi * double(disc));
  EXPECT_GT(disc, 3000);
  EXPECT_LT(double(rayWrong), 1.05 * outline);
  EXPECT_EQ(test::holesInside(rays, view.camera, {0, 0, 0}, 0.8, 0.1), 0);
  view.mode = DvtRenderMode::Cubes;
  const Image cubes = renderTree(streams, view);
  const auto [cubeWrong, same] = test::silhouetteMismatch(cubes, view.camera, {0, 0, 0}, 0.8);
  EXPECT_EQ(same, disc);
  EXPECT_LT(double(cubeWrong), 2.0 * outline);
  // The GPU tree drawn from its own buffers makes the same pictures.
  const Image direct = renderTree(dvt::gpuTreeBuffers(tree.passes()), tree.nodeCount(), frame, view);
  EXPECT_TRUE(direct.pixels == cubes.pixels);
  view.mode = DvtRenderMode::RayCast;
  EXPECT_TRUE(renderTree(dvt::gpuTreeBuffers(tree.passes()), tree.nodeCount(), frame, view).pixels == rays.pixels);
}

// A 256^3 grid (coordinates in the hundreds): a ray that reaches a leaf's face lands on it within a
// float's rounding, and must go on into the next leaf, not back into the one it leaves, whichever way
// it looks (the rays of a straight view run along the split planes).
TEST(DvtRender, RaysOnALargeGridSlipThroughNoLeaf) {
  test::glContext();
  const dvt::TreeFrame frame = dvt::frameAround({-1, -1, -1}, {1, 1, 1}, 8);
  dvt::DynamicVolumeTree tree(dvt::VolumeTree::empty(frame), dvt::makeCpuTreePasses());
  tree.write(dvt::rasterise(*dvt::parseBrush("sphere:0,0,0,0.8"), frame, 24), dvt::Op::Union);
  const dvt::VolumeTree streams = tree.tree();
  for (const Vec3 direction : {Vec3{0, 1, 0}, Vec3{-1, 0, 0}, Vec3{0.3, 1, 0}}) {
    const DvtView view{.camera = Camera::framing(insideBounds(streams), 201, 151, direction)};
    EXPECT_EQ(test::holesInside(renderTree(streams, view), view.camera, {0, 0, 0}, 0.8, 0.05), 0) << direction.x << "," << direction.y;
  }
}

}  // namespace
}  // namespace isoatlas::viewer
