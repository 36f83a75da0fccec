// Pictures of a dynamic volume tree: the ray caster and the cubes against a sphere's true silhouette,
// and a GPU tree's own buffers against its streams uploaded.
#include <gtest/gtest.h>

#include <numbers>

#include "levelset/dvt/cpu_tree_passes.h"
#include "levelset/dvt/dynamic_volume_tree.h"
#include "levelset/dvt/gpu_tree_passes.h"
#include "levelset/dvt/rasterise.h"
#include "levelset/dvt/volume_solid.h"
#include "tests/gl_context.h"
#include "viewer/dvt_render.h"

namespace isoatlas::viewer {
namespace {
namespace dvt = levelset::dvt;

bool drawn(const Image& image, int x, int y) { return image.at(x, y)[0] < 250 || image.at(x, y)[2] < 250; }

// Pixels where the picture and the true silhouette of a sphere (a ray through the pixel's centre
// meets it) disagree, and the silhouette's pixel count.
std::pair<std::int64_t, std::int64_t> silhouetteMismatch(const Image& image, const Camera& c, const Vec3& centre, double radius) {
  const Vec3 forward = (c.target - c.eye) * (1 / norm(c.target - c.eye));
  Vec3 right = cross(forward, c.up);
  right = right * (1 / norm(right));
  const Vec3 up = cross(right, forward);
  const double t = std::tan(c.fovDegrees * std::numbers::pi / 360), aspect = double(c.width) / c.height;
  std::int64_t wrong = 0, inside = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const double u = (2 * (x + 0.5) / c.width - 1) * t * aspect, v = (1 - 2 * (y + 0.5) / c.height) * t;
      Vec3 d = forward + right * u + up * v;
      d = d * (1 / norm(d));
      const Vec3 m = c.eye - centre;
      const double b = dot(m, d), q = dot(m, m) - radius * radius;
      const bool hit = b * b - q >= 0 && -b + std::sqrt(std::max(b * b - q, 0.0)) > 0;
      inside += hit;
      wrong += hit != drawn(image, x, y);
    }
  return {wrong, inside};
}

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
  const auto [rayWrong, disc] = silhouetteMismatch(rays, view.camera, {0, 0, 0}, 0.8);
  const double outline = 2 * std::sqrt(std::numbers::pi * double(disc));
  EXPECT_GT(disc, 3000);
  EXPECT_LT(double(rayWrong), 1.05 * outline);
  view.mode = DvtRenderMode::Cubes;
  const Image cubes = renderTree(streams, view);
  const auto [cubeWrong, same] = silhouetteMismatch(cubes, view.camera, {0, 0, 0}, 0.8);
  EXPECT_EQ(same, disc);
  EXPECT_LT(double(cubeWrong), 2.0 * outline);
  // The GPU tree drawn from its own buffers makes the same pictures.
  const Image direct = renderTree(dvt::gpuTreeBuffers(tree.passes()), tree.nodeCount(), frame, view);
  EXPECT_TRUE(direct.pixels == cubes.pixels);
  view.mode = DvtRenderMode::RayCast;
  EXPECT_TRUE(renderTree(dvt::gpuTreeBuffers(tree.passes()), tree.nodeCount(), frame, view).pixels == rays.pixels);
}

}  // namespace
}  // namespace isoatlas::viewer
