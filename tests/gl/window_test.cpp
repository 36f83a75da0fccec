// A GLFW window with a GL 4.5 core context: cleared to a colour that is read back exactly.
// Runs under xvfb-run (ctest wraps it); GLFW 3.3 has no headless platform.
#include <gtest/gtest.h>

#include "core/gl/context.h"
#include "core/gl/resources.h"

namespace isoatlas::gl {
namespace {

TEST(GlWindow, OpensAndClearsToAColour) {
  auto ctx = Context::window(64, 48, "isoatlas test", false);
  EXPECT_GE(ctx->info().major * 10 + ctx->info().minor, 45);
  EXPECT_EQ(ctx->info().platform, "GLFW window");
  Framebuffer fbo(64, 48);
  fbo.bind();
  glClearColor(0.25f, 0.5f, 1.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  const auto rgba = fbo.readRgba();
  ASSERT_EQ(rgba.size(), 64u * 48u * 4u);
  EXPECT_NEAR(rgba[0], 64, 1);
  EXPECT_NEAR(rgba[1], 128, 1);
  EXPECT_EQ(rgba[2], 255);
  EXPECT_EQ(rgba[rgba.size() - 1], 255);
  checkErrors("window test");
}

}  // namespace
}  // namespace isoatlas::gl
