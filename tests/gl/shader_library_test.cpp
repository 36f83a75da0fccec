#include <gtest/gtest.h>

#include "core/error.h"
#include "core/gl/shader_library.h"

namespace isoatlas::gl {
namespace {

TEST(ShaderLibrary, IncludesAreExpandedInPlace) {
  const std::string s = shaderSource("tests/gl/shaders/scramble.comp");
  EXPECT_NE(s.find("uint scramble(uint i)"), std::string::npos);
  EXPECT_EQ(s.find("#include"), std::string::npos);
  EXPECT_LT(s.find("#version 450"), s.find("uint scramble"));
}

TEST(ShaderLibrary, MissingShaderIsAnError) { EXPECT_THROW(shaderSource("no/such/shader.comp"), Error); }

}  // namespace
}  // namespace isoatlas::gl
