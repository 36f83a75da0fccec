// A tessellation pipeline whose triangles are captured by transform feedback and counted: a quad
// patch at integer level L with equal spacing yields 2 L^2 triangles, whose (u,v) lie on the L x L grid.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/gl/context.h"
#include "core/gl/program.h"
#include "core/gl/resources.h"
#include "kTestShaders.h"
#include "tests/gl_context.h"

namespace isoatlas::gl {
namespace {

TEST(GlTessellation, QuadPatchTriangleCountsAndCoordinates) {
  const Program& p = test::glContext().program(
      {kTestShaders, {"tests/gl/shaders/patch.vert", "tests/gl/shaders/levels.tesc", "tests/gl/shaders/quad.tese"}, {}, {"uvw"}});
  Framebuffer fbo(8, 8);  // EGL surfaceless has no default framebuffer, even with rasterizer discard
  fbo.bind();
  VertexArray vao;
  vao.bind();
  glPatchParameteri(GL_PATCH_VERTICES, 4);
  glEnable(GL_RASTERIZER_DISCARD);
  for (int level : {1, 4, 7, 16}) {
    const std::size_t expectedTriangles = std::size_t(2 * level * level);
    Buffer captured(expectedTriangles * 3 * 3 * sizeof(float) * 2);  // room for twice the expected output
    GLuint query = 0;
    glCreateQueries(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN, 1, &query);
    p.use();
    glUniform1f(p.uniform("level"), float(level));
    glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, captured.id());
    glBeginQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN, query);
    glBeginTransformFeedback(GL_TRIANGLES);
    glDrawArrays(GL_PATCHES, 0, 4);
    glEndTransformFeedback();
    glEndQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN);
    GLuint written = 0;
    glGetQueryObjectuiv(query, GL_QUERY_RESULT, &written);
    glDeleteQueries(1, &query);
    checkErrors("tessellation draw");
    ASSERT_EQ(written, expectedTriangles) << "level " << level;

    // Every captured vertex sits on the level x level grid of the unit square, and all grid points appear.
    const auto data = captured.read<float>(expectedTriangles * 9);
    std::set<std::pair<int, int>> grid;
    double area = 0;
    for (std::size_t t = 0; t < expectedTriangles; ++t) {
      const float* v = &data[t * 9];
      for (int c = 0; c < 3; ++c) {
        const double u = v[3 * c] * level, w = v[3 * c + 1] * level;
        ASSERT_NEAR(u, std::round(u), 1e-4);
        ASSERT_NEAR(w, std::round(w), 1e-4);
        ASSERT_FLOAT_EQ(v[3 * c + 2], 1.0f);
        grid.insert({int(std::lround(u)), int(std::lround(w))});
      }
      area += std::abs((v[3] - v[0]) * (v[7] - v[1]) - (v[6] - v[0]) * (v[4] - v[1])) / 2;
    }
    EXPECT_EQ(grid.size(), std::size_t((level + 1) * (level + 1)));
    EXPECT_NEAR(area, 1.0, 1e-5) << "the triangles tile the unit square";
  }
  glDisable(GL_RASTERIZER_DISCARD);
}

}  // namespace
}  // namespace isoatlas::gl
