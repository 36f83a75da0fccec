// The mesh renderer draws what it is given: a sphere's silhouette covers pi r^2 of the picture, the
// background stays background, and the side facing the camera is lit.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/gl_context.h"
#include "render/mesh_render.h"

namespace isoatlas::render {
namespace {

Mesh uvSphere(int rings, int segments, double r) {
  Mesh m;
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double t = M_PI * i / rings, p = 2 * M_PI * j / segments;
      m.positions.push_back({r * std::sin(t) * std::cos(p), r * std::sin(t) * std::sin(p), r * std::cos(t)});
    }
  auto id = [&](int i, int j) { return std::uint32_t(i * segments + (j % segments)); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      m.addFace({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.addFace({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

TEST(MeshRender, SphereSilhouetteAndShading) {
  test::glContext();
  const Mesh sphere = uvSphere(48, 96, 2.0);
  const Image img = renderMesh(sphere, {.width = 200, .height = 200});
  ASSERT_EQ(img.width, 200);
  std::int64_t covered = 0;
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 200; ++x) covered += img.at(x, y)[0] != 255 || img.at(x, y)[1] != 255 || img.at(x, y)[2] != 255;
  // Framed on the bounding box's projection (a square of side 4), with a 5 % margin.
  const double pixelsPerUnit = 100 / (2 * 1.05);
  const double expected = M_PI * std::pow(2.0 * pixelsPerUnit, 2);
  EXPECT_NEAR(double(covered), expected, 0.03 * expected);
  const std::uint8_t* centre = img.at(100, 100);
  EXPECT_GT(centre[0], 150) << "the side facing the camera is lit";
  const std::uint8_t* corner = img.at(2, 2);
  EXPECT_EQ(corner[0], 255);
}

}  // namespace
}  // namespace isoatlas::render
