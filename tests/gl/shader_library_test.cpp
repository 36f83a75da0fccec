#include <gtest/gtest.h>

#include "core/error.h"
#include "core/gl/shader_library.h"
#include "kTestShaders.h"

namespace isoatlas::gl {
namespace {

TEST(ShaderLibrary, IncludesAreExpandedInPlace) {
  const std::string s = shaderSource(kTestShaders, "tests/gl/shaders/scramble.comp");
  EXPECT_NE(s.find("uint scramble(uint i)"), std::string::npos);
  EXPECT_EQ(s.find("#include"), std::string::npos);
  EXPECT_LT(s.find("#version 450"), s.find("uint scramble"));
}

TEST(ShaderLibrary, MissingShaderIsAnError) { EXPECT_THROW(shaderSource(kTestShaders, "no/such/shader.comp"), Error); }

// Each library embeds its own folder's shaders: the tests' table holds tests/gl/shaders and nothing
// of the libraries (their shaders compile only through their own tables).
TEST(ShaderLibrary, ATableHoldsItsOwnFolderOnly) {
  for (const EmbeddedShader* s = kTestShaders; s->path; ++s)
    EXPECT_EQ(std::string(s->path).rfind("tests/gl/shaders/", 0), 0u) << s->path;
  EXPECT_NO_THROW(shaderSource(kTestShaders, "tests/gl/shaders/common.glsl"));
  EXPECT_THROW(shaderSource(kTestShaders, "levelset/shaders/update.comp"), Error);
}

}  // namespace
}  // namespace isoatlas::gl
