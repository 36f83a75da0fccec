// A compute shader with a known result, on whatever GL the machine has (llvmpipe in CI).
#include <gtest/gtest.h>

#include <cstdlib>

#include "core/gl/context.h"
#include "core/gl/program.h"
#include "core/gl/resources.h"
#include "kTestShaders.h"
#include "tests/gl_context.h"
#include "tests/test_util.h"

namespace isoatlas::gl {
namespace {

TEST(GlCompute, ContextIsOpenGL45Core) {
  const Context& ctx = test::glContext();
  EXPECT_GE(ctx.info().major * 10 + ctx.info().minor, 45);
  EXPECT_GE(ctx.info().maxComputeWorkGroupInvocations, 1024);  // the spec's minimum
  EXPECT_GE(ctx.info().maxTessellationLevel, 64);
}

TEST(GlCompute, FloatDefinesReadBackExactly) {
  for (const float value : {3.0f, 0.25f, 1e-7f, 1.0f / 3.0f, -2.5e10f, 0.0f}) {
    const std::string literal = glslFloat(value);
    EXPECT_EQ(std::strtof(literal.c_str(), nullptr), value) << literal;
    EXPECT_NE(literal.find_first_of(".e"), std::string::npos) << literal << " would be an int in GLSL";
  }
}

TEST(GlCompute, ScrambleMatchesTheCpu) {
  Context& ctx = test::glContext();
  const std::uint32_t count = 10007;  // not a multiple of the work-group size
  std::vector<std::uint32_t> input(count);
  for (std::uint32_t i = 0; i < count; ++i) input[i] = i * 7919u + 13u;
  Buffer src = Buffer::of(input), dst(count * sizeof(std::uint32_t));
  const Program& p = ctx.compute(kTestShaders, "tests/gl/shaders/scramble.comp", {{"OFFSET", "5u"}});
  src.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
  dst.bindBase(GL_SHADER_STORAGE_BUFFER, 1);
  p.use();
  glUniform1ui(p.uniform("count"), count);
  TimerQuery timer;  // exercised, not asserted: a software rasteriser may report any elapsed time
  timer.begin();
  p.dispatch((count + 63) / 64);
  timer.end();
  timer.milliseconds();
  const auto out = dst.read<std::uint32_t>(count);
  for (std::uint32_t i = 0; i < count; ++i) ASSERT_EQ(out[i], input[i] * 2654435761u + i + 5u) << "at " << i;
  checkErrors("test");
}

TEST(GlCompute, CompileErrorsAreReported) {
  Context& ctx = test::glContext();
  // Without OFFSET defined the shader does not compile; the error names the file.
  const Error e = test::thrownError([&] { ctx.compute(kTestShaders, "tests/gl/shaders/scramble.comp"); }, "a shader without OFFSET");
  EXPECT_NE(std::string(e.what()).find("scramble.comp"), std::string::npos) << e.what();
}

}  // namespace
}  // namespace isoatlas::gl
