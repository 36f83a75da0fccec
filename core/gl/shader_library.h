// Shaders embedded at build time, one table per library (cmake/EmbedShaders.cmake), looked up by
// their path from the repository root, e.g. "levelset/shaders/update.comp". `#include "file"` in a
// shader is resolved in the same table, against the including file's folder first, then the root.
#pragma once
#include <initializer_list>
#include <string>
#include <vector>

namespace isoatlas::gl {

struct EmbeddedShader {
  const char* path;
  const char* source;
};

// Source of `path` from `files` (a table ending with {nullptr, nullptr}) with every #include expanded;
// throws Error if a file is missing from the table or includes loop.
std::string shaderSource(const EmbeddedShader* files, const std::string& path);

// Several libraries' tables as one (ending with {nullptr, nullptr}), for shaders that include files
// of another library; keep it alive as long as the programs compiled from it may be rebuilt.
std::vector<EmbeddedShader> joinShaderTables(std::initializer_list<const EmbeddedShader*> tables);

}  // namespace isoatlas::gl
