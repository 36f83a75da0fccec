// Pictures of a dynamic volume tree: the ray caster and the cubes against a sphere's true silhouette
// (no holes inside it, on a small grid and a large one) and the rays against its true shading, and a
// GPU tree's own buffers against its streams uploaded.
#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>
#include <numeric>
#include <vector>

#include "edit/dvt/cpu_tree_passes.h"
#include "edit/dvt/dynamic_volume_tree.h"
#include "edit/dvt/gpu_tree_passes.h"
#include "edit/solids/rasterise.h"
#include "edit/solids/volume_solid.h"
#include "tests/gl_context.h"
#include "tests/render/silhouette.h"
#include "render/dvt_render.h"

namespace isoatlas::render {
namespace {
namespace dvt = edit::dvt;

TEST(DvtRender, SilhouettesOfASphereAndTheGpuTreesOwnBuffers) {
  test::glContext();
  const dvt::TreeFrame frame = dvt::frameAround({-1, -1, -1}, {1, 1, 1}, 5);
  dvt::DynamicVolumeTree tree(dvt::VolumeTree::empty(frame), dvt::makeGpuTreePasses());
  tree.write(dvt::rasterise(*dvt::parseBrush("sphere:0,0,0,0.8"), frame, 16), dvt::Op::Union);
  const dvt::VolumeTree streams = tree.tree();
  DvtView view{.camera = Camera::framing(insideBounds(streams), 160, 120, {0.3, 1, -0.2})};
  const Image rays = renderTree(streams, view);
  // Voxels of ~1.5-3 pixels here: the rays follow the outline of the field between the leaves, the
  // cubes miss it by their steps.
  const auto [rayWrong, disc] = test::silhouetteMismatch(rays, view.camera, {0, 0, 0}, 0.8);
  const double outline = 2 * std::sqrt(std::numbers::pi * double(disc));
  EXPECT_GT(disc, 3000);
  EXPECT_LT(double(rayWrong), 0.25 * outline);
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

// The ray caster against a sphere lit analytically (shading.glsl's headlight, white): the hit on the
// leaves' interpolated field and its gradient give the sphere's own shading away from the outline,
// with no leaf-sized terraces or facets. Built from a level set's kind of phi (four times steeper than
// a distance, clamped at 3), which the tree turns into distances.
TEST(DvtRender, RaysLightTheSurfaceBetweenTheLeaves) {
  test::glContext();
  Volume phi = Volume::zeros({32, 32, 32}, ScalarType::Float32);
  const Vec3 centre{15.4, 15.7, 15.2};
  const double radius = 12.3;
  for (std::int64_t k = 0; k < 32; ++k)
    for (std::int64_t j = 0; j < 32; ++j)
      for (std::int64_t i = 0; i < 32; ++i)
        phi.setValue(phi.index(i, j, k), std::clamp(4 * (radius - norm(Vec3{double(i), double(j), double(k)} - centre)), -3.0, 3.0));
  const dvt::TreeFrame frame = dvt::frameOf(phi);
  dvt::DynamicVolumeTree tree(dvt::VolumeTree::empty(frame), dvt::makeCpuTreePasses());
  tree.write(dvt::rasterise(dvt::VolumeSolid(phi), frame, frame.voxelDepth()), dvt::Op::Union);
  const DvtView view{.camera = Camera::framing(insideBounds(tree.tree()), 240, 180, {0.3, 1, -0.2}), .colour = {1, 1, 1}};
  const Image rays = renderTree(tree.tree(), view);
  const Vec3 light = unit(Vec3{0.3, 0.5, 0.8});
  std::vector<double> errors;
  for (int y = 0; y < rays.height; ++y)
    for (int x = 0; x < rays.width; ++x) {
      const Vec3 d = view.camera.rayThrough(x + 0.5, y + 0.5), m = centre - view.camera.eye;
      const double along = dot(m, d), miss2 = dot(m, m) - along * along;
      if (miss2 > 0.8 * 0.8 * radius * radius) continue;  // away from the outline, where a pixel's shade moves fast
      const Vec3 hit = view.camera.eye + d * (along - std::sqrt(radius * radius - miss2)), n = unit(hit - centre);
      const double lit = 0.15 + 0.75 * std::abs(dot(n, unit(view.camera.eye - hit))) + 0.15 * std::max(dot(n, light), 0.0);
      errors.push_back(std::abs(double(rays.at(x, y)[0]) - 255 * lit));
    }
  ASSERT_GT(errors.size(), 5000u);
  std::sort(errors.begin(), errors.end());
  const double mean = std::accumulate(errors.begin(), errors.end(), 0.0) / double(errors.size());
  EXPECT_LT(mean, 3.0);
  EXPECT_LT(errors[errors.size() * 99 / 100], 15.0);
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
}  // namespace isoatlas::render
