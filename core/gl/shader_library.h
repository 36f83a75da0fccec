// The shaders embedded at build time (cmake/EmbedShaders.cmake), looked up by their path from the
// repository root, e.g. "levelset/shaders/update.comp". `#include "file"` in a shader is resolved
// against the including file's folder first, then the repository root.
#pragma once
#include <string>

namespace isoatlas::gl {

struct EmbeddedShader {
  const char* path;
  const char* source;
};
extern const EmbeddedShader kEmbeddedShaders[];  // ends with {nullptr, nullptr}

// Source of `path` with every #include expanded; throws Error if a file is missing or includes loop.
std::string shaderSource(const std::string& path);

}  // namespace isoatlas::gl
