// Program: a linked GL program from embedded shader files (see shader_library.h). `defines` are
// inserted after the #version line of every stage, as "#define NAME VALUE" lines.
// A program belongs to the context current when it was linked; use() and dispatch() check that this
// context is current and throw Error otherwise (a GL call made in another context, or none, would
// silently act on the wrong objects). GPU algorithms get their programs from Context::program(),
// which compiles each once per context.
#pragma once
#include <epoxy/gl.h>

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/gl/shader_library.h"

namespace isoatlas::gl {

using Defines = std::vector<std::pair<std::string, std::string>>;

// A float as a GLSL float literal that reads back as the same value (std::to_string keeps six
// decimals, so 1e-7 would arrive as 0.000000).
std::string glslFloat(float value);

// What to compile: shader files from one library's table, stages by file extension (.comp alone, or
// .vert .tesc .tese .geom .frag), defines, and outputs to record with transform feedback (interleaved).
struct ProgramSource {
  const EmbeddedShader* files;
  std::vector<std::string> paths;
  Defines defines;
  std::vector<const char*> varyings;
  std::string key() const;  // equal for sources that compile to the same program
};

class Program {
public:
  // Compiles and links in the current context (Context::current(), checked).
  explicit Program(const ProgramSource& source);
  Program() = default;
  ~Program();
  Program(Program&& o) noexcept
      : id_(std::exchange(o.id_, 0)), context_(std::exchange(o.context_, 0)), name_(std::move(o.name_)) {}
  Program& operator=(Program&& o) noexcept;

  GLuint id() const { return id_; }
  void use() const;
  GLint uniform(const char* name) const { return glGetUniformLocation(id_, name); }
  // Runs a compute program over `groups` work groups and waits for its writes to be visible.
  void dispatch(GLuint x, GLuint y = 1, GLuint z = 1, GLbitfield barrier = GL_ALL_BARRIER_BITS) const;
  // The same with the grid read from `args` at `offset` (three words an earlier pass wrote, ordered
  // before this by a GL_COMMAND_BARRIER_BIT), so the host need not read a size back to dispatch.
  void dispatchIndirect(GLuint args, GLintptr offset, GLbitfield barrier = GL_ALL_BARRIER_BITS) const;

private:
  GLuint id_ = 0;
  std::uint64_t context_ = 0;  // the serial of the context it was linked in (Context::serial)
  std::string name_;  // the first file, for messages
};

// The work-group grid for `groups` groups: at most 65535 along x (the limit every GL 4.5 driver
// allows), the rest along y. Shaders number their group gl_WorkGroupID.y * gl_NumWorkGroups.x +
// gl_WorkGroupID.x and return past the count. Throws Error (Failure) past 65535 x 65535 groups.
std::array<GLuint, 2> dispatchGrid(std::uint64_t groups);

}  // namespace isoatlas::gl
