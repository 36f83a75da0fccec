// The one-context rules: programs compiled once per context, GL work refused when the context it was
// made in is not current, contexts counted.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <thread>

#include "core/error.h"
#include "core/gl/context.h"
#include "core/gl/program.h"
#include "core/gl/resources.h"
#include "kTestShaders.h"

namespace isoatlas::gl {
namespace {

const char* kScramble = "tests/gl/shaders/scramble.comp";

// Runs `p` (scramble.comp) over one value and returns the result.
std::uint32_t scrambleOne(const Program& p, std::uint32_t value) {
  Buffer src(4, &value), dst(4);
  src.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
  dst.bindBase(GL_SHADER_STORAGE_BUFFER, 1);
  p.use();
  glUniform1ui(p.uniform("count"), 1);
  p.dispatch(1);
  return dst.read<std::uint32_t>(1)[0];
}

// Sizes GL takes as 32-bit signed: refused, named, past 2^31 - 1, instead of wrapping negative;
// dispatches past the grid's 65535 x 65535 groups likewise.
TEST(GlSizes, SizesPastWhatGlTakesAreRefusedNamed) {
  EXPECT_EQ(gl::glSize(2147483647, "x"), 2147483647);
  try {
    gl::glSize(2147483648ull, "drawing the mesh's corners");
    ADD_FAILURE() << "2^31 was taken";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "drawing the mesh's corners: 2147483648 is more than OpenGL takes in one call (2^31 - 1)");
  }
  EXPECT_EQ(gl::dispatchGrid(65535ull * 65535)[1], 65535u);
  EXPECT_THROW(gl::dispatchGrid(65535ull * 65535 + 1), Error);
}

TEST(GlContext, ProgramsCompileOncePerContext) {
  auto ctx = Context::headless();
  EXPECT_EQ(ctx->programsCompiled(), 0);
  const Program& a = ctx->compute(kTestShaders, kScramble, {{"OFFSET", "5u"}});
  const Program& again = ctx->compute(kTestShaders, kScramble, {{"OFFSET", "5u"}});
  EXPECT_EQ(&a, &again);
  EXPECT_EQ(ctx->programsCompiled(), 1);
  const Program& other = ctx->compute(kTestShaders, kScramble, {{"OFFSET", "6u"}});
  EXPECT_NE(a.id(), other.id());
  EXPECT_EQ(ctx->programsCompiled(), 2);
  EXPECT_EQ(scrambleOne(other, 3) - scrambleOne(a, 3), 1u);  // each keeps its own define
  EXPECT_EQ(ctx->programsCompiled(), 2);
}

TEST(GlContext, WorkWithoutItsContextCurrentFails) {
  auto ctx = Context::headless();
  const Program& p = ctx->compute(kTestShaders, kScramble, {{"OFFSET", "0u"}});
  EXPECT_EQ(&Context::current(), ctx.get());
  ctx->releaseCurrent();
  EXPECT_FALSE(ctx->isCurrent());
  EXPECT_THROW(Context::current(), Error);
  EXPECT_THROW(p.use(), Error);
  EXPECT_THROW(p.dispatch(1), Error);
  ctx->makeCurrent();
  EXPECT_NO_THROW(scrambleOne(p, 7));
}

// A context current on one thread cannot be made current on another (EGL refuses it): makeCurrent
// says so there, and that thread still has no context; released where it was, the other thread can
// take it and work in it.
TEST(GlContext, AContextCurrentOnAnotherThreadIsRefused) {
  auto ctx = Context::headless();
  const Program& p = ctx->compute(kTestShaders, kScramble, {{"OFFSET", "0u"}});
  std::string refused;
  bool noContext = false;
  std::thread([&] {
    try {
      ctx->makeCurrent();
    } catch (const Error& e) {
      refused = e.what();
    }
    try {
      Context::current();
    } catch (const Error&) {
      noContext = true;
    }
  }).join();
  EXPECT_NE(refused.find("current on another one"), std::string::npos) << refused;
  EXPECT_TRUE(noContext);
  ctx->releaseCurrent();
  std::uint32_t scrambled = 0;
  std::thread([&] {
    ctx->makeCurrent();
    scrambled = scrambleOne(p, 7);
    ctx->releaseCurrent();
  }).join();
  ctx->makeCurrent();
  EXPECT_EQ(scrambled, scrambleOne(p, 7));
}

TEST(GlContext, AProgramRefusesAnotherContext) {
  const int before = Context::made();
  auto first = Context::headless();
  const Program& p = first->compute(kTestShaders, kScramble, {{"OFFSET", "0u"}});
  auto second = Context::headless();  // current now
  EXPECT_EQ(Context::made(), before + 2);
  EXPECT_TRUE(second->isCurrent());
  EXPECT_THROW(p.dispatch(1), Error);
  // The second context compiles its own copy.
  const Program& q = second->compute(kTestShaders, kScramble, {{"OFFSET", "0u"}});
  EXPECT_EQ(second->programsCompiled(), 1);
  const std::uint32_t expected = scrambleOne(q, 11);
  first->makeCurrent();
  EXPECT_EQ(scrambleOne(p, 11), expected);
  // Destroyed in the order they were made: each goes with its own programs.
  first.reset();
  EXPECT_THROW(Context::current(), Error);
  second->makeCurrent();
  EXPECT_EQ(scrambleOne(q, 11), expected);
  second.reset();
  EXPECT_THROW(Context::current(), Error);
}

// Objects are made only in a current context, and destroyed only while theirs is current: otherwise a
// debug build aborts (so a test that leaves an object to outlive its context fails), and a release
// build leaves the object to its context and counts it. Checks that destroying `buffer` now is
// refused; in release builds it is then gone, in debug builds still there.
void expectDeleteRefused(std::unique_ptr<Buffer>& buffer) {
#ifdef NDEBUG
  const int before = orphanedObjects();
  buffer.reset();
  EXPECT_EQ(orphanedObjects(), before + 1);
#else
  EXPECT_DEATH(buffer.reset(), "context it was made in is not current");
#endif
}

TEST(GlContext, ObjectsNeedTheirContextCurrent) {
  auto ctx = Context::headless();
  auto buffer = std::make_unique<Buffer>(16);
  ctx->releaseCurrent();
  EXPECT_THROW(Buffer(16), Error);
  EXPECT_THROW(Texture::texture2D(GL_R32F, 4, 4), Error);
  expectDeleteRefused(buffer);
  ctx->makeCurrent();
  buffer.reset();
}

// An object that outlives its context, while a newer context is current: it must not delete a name
// of the newer one (a stored pointer could even point at the newer context, made at the old address).
TEST(GlContext, AnObjectOutlivingItsContextTouchesNoOther) {
  auto old = Context::headless();
  auto buffer = std::make_unique<Buffer>(16);
  old.reset();
  auto current = Context::headless();
  Buffer other(16);  // in the new context; the same name as the orphan's, most likely
  expectDeleteRefused(buffer);
  static_cast<void>(buffer.release());  // (debug builds) its context is gone: nothing can delete it
  std::uint32_t value = 7;
  EXPECT_NO_THROW(other.upload(&value, 4));
  EXPECT_EQ(other.read<std::uint32_t>(1)[0], 7u);
  checkErrors("after the orphan");
}

}  // namespace
}  // namespace isoatlas::gl
