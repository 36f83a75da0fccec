// A compute shader with a known result, on whatever GL the machine has (llvmpipe in CI).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <numeric>

#include "core/gl/context.h"
#include "core/gl/gpu_scan.h"
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

// fillZero zeroes the first bytes, rounded up to words, and nothing past them, over sizes that end a
// work group's quad, split one and pass the end; the caller's program and bindings stay as they were.
// Both ways: the driver's clear (a software renderer's) and the compute shader's (a GPU's).
TEST(GlCompute, FillZeroClearsTheFirstWordsAndKeepsTheCallersState) {
  Context& ctx = test::glContext();
  const std::uint32_t count = 5000;
  const std::vector<std::uint32_t> pattern(count, 0xdeadbeefu);
  for (const bool byShader : {false, true})
  for (const std::size_t bytes : {std::size_t(0), std::size_t(4), std::size_t(13), std::size_t(16), std::size_t(4100),
                                  std::size_t(4 * 4097 + 8), std::size_t(4 * count), std::size_t(4 * count + 100)}) {
    Buffer buffer = Buffer::of(pattern), other = Buffer::of(pattern);
    const Program& p = ctx.compute(kTestShaders, "tests/gl/shaders/scramble.comp", {{"OFFSET", "5u"}});
    p.use();
    other.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
    if (byShader)
      buffer.zeroWords(std::min<std::size_t>((bytes + 3) / 4, count));
    else
      buffer.fillZero(bytes);
    GLint program = 0, bound = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &program);
    glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, 0, &bound);
    EXPECT_EQ(GLuint(program), p.id());
    EXPECT_EQ(GLuint(bound), other.id());
    const auto out = buffer.read<std::uint32_t>(count);
    const std::size_t zeroed = std::min<std::size_t>((bytes + 3) / 4, count);
    for (std::size_t i = 0; i < count; ++i) ASSERT_EQ(out[i], i < zeroed ? 0u : 0xdeadbeefu) << "word " << i << " of a fill of " << bytes << " bytes";
  }
  // A buffer of a size in bytes that is no multiple of a word: cleared byte by byte.
  const std::vector<std::uint8_t> bytes(4099, 0xab);
  Buffer odd = Buffer::of(bytes);
  odd.fillZero(4098);
  const auto out = odd.read<std::uint8_t>(bytes.size());
  for (std::size_t i = 0; i < out.size(); ++i) ASSERT_EQ(out[i], i < 4098 ? 0 : 0xab) << "byte " << i;
  checkErrors("test");
}

// A float texture read in bands of whole rows (Texture::readRedFloats, as a phi pool past 2 GiB
// must be) gives every texel where one whole read does, whatever the band: one row, a few with a
// short last band, all of them.
TEST(GlCompute, FloatTexturesReadInBandsAsWhole) {
  test::glContext();
  const int w = 37, h = 23;
  std::vector<float> texels(std::size_t(w) * h);
  for (std::size_t i = 0; i < texels.size(); ++i) texels[i] = float(i) * 0.5f - 100.0f;
  const Texture t = Texture::texture2D(GL_R32F, w, h);
  glTextureSubImage2D(t.id(), 0, 0, 0, w, h, GL_RED, GL_FLOAT, texels.data());
  for (const std::size_t band : {std::size_t(1), std::size_t(w * 4), std::size_t(w * 4 * 5), std::size_t(w * 4 * 5 + 7), Texture::kReadBandBytes}) {
    std::vector<float> out;
    t.readRedFloats(out, band);
    ASSERT_EQ(out, texels) << "bands of " << band << " bytes";
  }
  checkErrors("test");
}

// Exclusive prefix sums against std::exclusive_scan, across one, two and three levels of the
// recursion; the device-count form scans as many as a buffer's word says, leaves the rest and reads
// nothing back (a count of 0 scans nothing); the kept block sums serve a larger scan after a smaller.
TEST(GlCompute, ScansMatchTheCpuWithTheCountFromTheHostOrTheDevice) {
  test::glContext();
  GpuScan scan;
  for (const std::uint32_t count : {1u, 1023u, 1024u, 1025u, 300000u, 1024u * 1024u + 4097u, 7u}) {
    std::vector<std::uint32_t> values(count + 100);
    for (std::uint32_t i = 0; i < values.size(); ++i) values[i] = (i * 2654435761u) >> 28;
    std::vector<std::uint32_t> want(values.size());
    std::exclusive_scan(values.begin(), values.begin() + count, want.begin(), 0u);
    std::copy(values.begin() + count, values.end(), want.begin() + count);
    const std::uint32_t total = std::accumulate(values.begin(), values.begin() + count, 0u);
    Buffer byHost = Buffer::of(values);
    EXPECT_EQ(scan.exclusive(byHost, count), total) << count;
    EXPECT_TRUE(byHost.read<std::uint32_t>(values.size()) == want) << count << " values, count from the host";
    Buffer byDevice = Buffer::of(values);
    const std::vector<std::uint32_t> counts{0u, count, 0u};
    const Buffer countWords = Buffer::of(counts);
    scan.exclusive(byDevice, countWords, 1, std::uint32_t(values.size()));
    EXPECT_TRUE(byDevice.read<std::uint32_t>(values.size()) == want) << count << " values, count from the device";
    Buffer none = Buffer::of(values);
    scan.exclusive(none, countWords, 0, std::uint32_t(values.size()));
    EXPECT_TRUE(none.read<std::uint32_t>(values.size()) == values) << "a count of 0 changed values";
    // A most far above the count (the tree's chains scan their node count against their capacity):
    // levels the count does not reach run with counts of one block or none.
    const std::uint32_t room = 2u * 1024u * 1024u + 5u;
    Buffer roomy(std::size_t(room) * 4);
    roomy.upload(values.data(), values.size() * 4);
    scan.exclusive(roomy, countWords, 1, room);
    EXPECT_TRUE(roomy.read<std::uint32_t>(values.size()) == want) << count << " values, room for 2^21 + 5";
  }
}

TEST(GlCompute, CompileErrorsAreReported) {
  Context& ctx = test::glContext();
  // Without OFFSET defined the shader does not compile; the error names the file.
  const Error e = test::thrownError([&] { ctx.compute(kTestShaders, "tests/gl/shaders/scramble.comp"); }, "a shader without OFFSET");
  EXPECT_NE(std::string(e.what()).find("scramble.comp"), std::string::npos) << e.what();
}

}  // namespace
}  // namespace isoatlas::gl
