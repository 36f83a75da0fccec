// The volume renderer reads the level set from its pages: a seeded ball's surface against its true
// silhouette, the same picture whatever the page size or the backend holding the pool, the scan only
// inside the ball as a region of interest, and the clipping plane's cut face with the contour where it
// cuts the ball.
#include <gtest/gtest.h>

#include <numbers>

#include "levelset/level_set.h"
#include "tests/gl_context.h"
#include "tests/render/silhouette.h"
#include "render/ray_pick.h"
#include "render/volume_render.h"

namespace isoatlas::render {
namespace {

// 40^3 voxels of 1.5 mm centred on the origin; intensity rising along x.
Volume scan() {
  Volume v = Volume::zeros({40, 40, 40}, ScalarType::Float32);
  v.spacing = {1.5, 1.5, 1.5};
  v.origin = {-29.25, -29.25, -29.25};
  for (std::int64_t k = 0; k < 40; ++k)
    for (std::int64_t j = 0; j < 40; ++j)
      for (std::int64_t i = 0; i < 40; ++i) v.setValue(v.index(i, j, k), 50 + 2.0 * double(i));
  return v;
}

constexpr double kRadius = 18;  // mm: 12 voxels

std::unique_ptr<levelset::LevelSet> ball(const Volume& v, int pageSize, levelset::Backend backend) {
  auto ls = std::make_unique<levelset::LevelSet>(v, levelset::SpeedParams{.target = 100, .width = 10, .alpha = 0.5},
                                                 levelset::LevelSetOptions{.backend = backend, .pageSize = pageSize});
  ls->addSphere(v.worldToIndex({0, 0, 0}), kRadius / 1.5);
  return ls;
}

TEST(VolumeRender, ReadsTheLevelSetFromItsPages) {
  test::glContext();
  const Volume v = scan();
  const auto ls = ball(v, 16, levelset::Backend::Cpu);
  VolumeRenderView view{.camera = Camera::framing({{-30, -30, -30}, {30, 30, 30}}, 160, 120, {0.3, 1, -0.2}),
                        .window = {50, 130}, .scan = false};
  const Image surface = renderVolume(v, *ls, view);
  const auto [wrong, disc] = test::silhouetteMismatch(surface, view.camera, {0, 0, 0}, kRadius);
  const double outline = 2 * std::sqrt(std::numbers::pi * double(disc));
  EXPECT_GT(disc, 1500);
  EXPECT_LT(double(wrong), 1.05 * outline) << "the surface meets the ball's silhouette within about a pixel";

  // Another page size lays the pool out otherwise; the GPU solver keeps it in its own texture.
  EXPECT_TRUE(renderVolume(v, *ball(v, 8, levelset::Backend::Cpu), view).pixels == surface.pixels);
  EXPECT_TRUE(renderVolume(v, *ball(v, 16, levelset::Backend::Gpu), view).pixels == surface.pixels);

  // The scan inside the ball only: nothing drawn outside its silhouette, the inside darker where the
  // scan is bright (x grows to the picture's right here).
  view.scan = true, view.insideOnly = true, view.surface = false, view.opacity = 0.3;
  const Image roi = renderVolume(v, *ls, view);
  const auto [roiWrong, roiDisc] = test::silhouetteMismatch(roi, view.camera, {0, 0, 0}, kRadius);
  EXPECT_EQ(roiDisc, disc);
  EXPECT_LT(double(roiWrong), 1.05 * outline);
}

TEST(VolumeRender, TheClippingPlaneShowsTheContourWhereItCutsTheBall) {
  test::glContext();
  const Volume v = scan();
  const auto ls = ball(v, 16, levelset::Backend::Cpu);
  // Looking along +y at the plane y = -6 mm, whose near side (y < -6) is cut away.
  Camera camera;
  camera.eye = {0, -200, 0}, camera.target = {0, 0, 0}, camera.width = 200, camera.height = 200;
  const VolumeRenderView view{.camera = camera, .window = {50, 130}, .clip = ClipPlane{{0, -6, 0}, {0, -1, 0}}};
  const Image image = renderVolume(v, *ls, view);
  // The contour: a circle of radius sqrt(18^2 - 6^2) mm on the plane, 194 mm from the eye.
  const double pixelsPerMm = camera.height / (2 * 194 * std::tan(camera.fovDegrees * std::numbers::pi / 360));
  const double expected = std::sqrt(kRadius * kRadius - 36) * pixelsPerMm;
  std::int64_t contour = 0, off = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* c = image.at(x, y);
      if (c[0] != 255 || c[1] != 224 || c[2] != 0) continue;
      ++contour;
      off += std::abs(std::hypot(x + 0.5 - 100, y + 0.5 - 100) - expected) > 2.0;
    }
  EXPECT_GT(double(contour), 2 * 3.14 * expected) << "a ring of contour pixels";
  EXPECT_EQ(off, 0) << "on the circle where the plane cuts the ball";
  // The cut face shows the scan: grey rising to the right (+x is the picture's right from -y).
  const std::uint8_t* left = image.at(55, 100);
  const std::uint8_t* right = image.at(145, 100);
  EXPECT_EQ(left[0], left[2]);
  EXPECT_LT(left[0], right[0]);
}

}  // namespace
}  // namespace isoatlas::render

namespace isoatlas::render {
namespace {

// The mouse's pick: a ray's first hit on a cube's triangles, or nothing.
TEST(RayPick, FirstHitOnTrianglesOrNone) {
  Mesh cube;
  cube.positions = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}};
  for (const auto& q : std::vector<std::array<std::uint32_t, 4>>{{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 3, 7, 4}, {1, 2, 6, 5}})
    cube.addFace({q[0], q[1], q[2]}), cube.addFace({q[0], q[2], q[3]});
  const auto hit = rayPick(cube, {0.3, -5, 0.2}, {0, 2, 0});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->x, 0.3, 1e-12);
  EXPECT_NEAR(hit->y, -1, 1e-12) << "the near face, not the far one";
  EXPECT_NEAR(hit->z, 0.2, 1e-12);
  EXPECT_FALSE(rayPick(cube, {0.3, -5, 0.2}, {0, -1, 0})) << "pointing away";
  EXPECT_FALSE(rayPick(cube, {3, -5, 0}, {0, 1, 0})) << "passing beside";
}

}  // namespace
}  // namespace isoatlas::render
