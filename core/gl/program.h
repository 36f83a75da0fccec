// Program: a linked GL program from embedded shader files (see shader_library.h). `defines` are
// inserted after the #version line of every stage, as "#define NAME VALUE" lines.
#pragma once
#include <epoxy/gl.h>

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace isoatlas::gl {

using Defines = std::vector<std::pair<std::string, std::string>>;

// A float as a GLSL float literal that reads back as the same value (std::to_string keeps six
// decimals, so 1e-7 would arrive as 0.000000).
std::string glslFloat(float value);

class Program {
public:
  static Program compute(const std::string& path, const Defines& defines = {});
  // Stages by file extension: .vert .tesc .tese .geom .frag.
  static Program graphics(const std::vector<std::string>& paths, const Defines& defines = {});
  // Like graphics(), recording the named outputs with transform feedback (interleaved).
  static Program graphicsWithFeedback(const std::vector<std::string>& paths, const std::vector<const char*>& varyings,
                                      const Defines& defines = {});

  Program() = default;
  ~Program();
  Program(Program&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
  Program& operator=(Program&& o) noexcept;

  GLuint id() const { return id_; }
  void use() const { glUseProgram(id_); }
  GLint uniform(const char* name) const { return glGetUniformLocation(id_, name); }
  // Runs a compute program over `groups` work groups and waits for its writes to be visible.
  void dispatch(GLuint x, GLuint y = 1, GLuint z = 1, GLbitfield barrier = GL_ALL_BARRIER_BITS) const;

private:
  static Program link(const std::vector<std::string>& paths, const Defines& defines,
                      const std::vector<const char*>& varyings);
  GLuint id_ = 0;
};

}  // namespace isoatlas::gl
