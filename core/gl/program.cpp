#include "core/gl/program.h"

#include "core/error.h"
#include "core/gl/context.h"
#include "core/gl/resources.h"
#include "core/gl/shader_library.h"
#include "core/gz_file.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>

namespace isoatlas::gl {
namespace {

GLenum stageOf(const std::string& path) {
  if (endsWith(path, ".comp")) return GL_COMPUTE_SHADER;
  if (endsWith(path, ".vert")) return GL_VERTEX_SHADER;
  if (endsWith(path, ".tesc")) return GL_TESS_CONTROL_SHADER;
  if (endsWith(path, ".tese")) return GL_TESS_EVALUATION_SHADER;
  if (endsWith(path, ".geom")) return GL_GEOMETRY_SHADER;
  if (endsWith(path, ".frag")) return GL_FRAGMENT_SHADER;
  throw Error("shader " + path + ": unknown stage (extension)", ErrorKind::Failure);
}

std::string withDefines(std::string source, const Defines& defines) {
  std::string block;
  for (const auto& [name, value] : defines) block += "#define " + name + " " + value + "\n";
  const auto version = source.find("#version");
  const auto lineEnd = version == std::string::npos ? 0 : source.find('\n', version) + 1;
  source.insert(lineEnd, block + "#line 2\n");
  return source;
}

GLuint compile(const EmbeddedShader* files, const std::string& path, const Defines& defines) {
  const std::string source = withDefines(shaderSource(files, path), defines);
  const GLuint shader = glCreateShader(stageOf(path));
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(std::size_t(length > 0 ? length : 1), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    glDeleteShader(shader);
    throw Error("shader " + path + " does not compile: " + log.c_str(), ErrorKind::Failure);
  }
  return shader;
}

}  // namespace

std::string glslFloat(float value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", double(value));
  std::string literal = text;
  if (literal.find_first_of(".e") == std::string::npos) literal += ".0";
  return literal;
}

std::string ProgramSource::key() const {
  std::string k = std::to_string(reinterpret_cast<std::uintptr_t>(files));
  for (const auto& p : paths) k += "|" + p;
  for (const auto& [name, value] : defines) k += "|" + name + "=" + value;
  for (const char* v : varyings) k += std::string("|out ") + v;
  return k;
}

Program::Program(const ProgramSource& source) : context_(Context::current().serial()), name_(source.paths.at(0)) {
  id_ = glCreateProgram();
  std::vector<GLuint> shaders;
  try {
    for (const auto& path : source.paths) shaders.push_back(compile(source.files, path, source.defines));
  } catch (...) {
    for (GLuint s : shaders) glDeleteShader(s);
    glDeleteProgram(std::exchange(id_, 0));
    throw;
  }
  for (GLuint s : shaders) glAttachShader(id_, s);
  if (!source.varyings.empty())
    glTransformFeedbackVaryings(id_, GLsizei(source.varyings.size()), source.varyings.data(), GL_INTERLEAVED_ATTRIBS);
  glLinkProgram(id_);
  for (GLuint s : shaders) glDeleteShader(s);
  GLint ok = 0;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(id_, GL_INFO_LOG_LENGTH, &length);
    std::string log(std::size_t(length > 0 ? length : 1), '\0');
    glGetProgramInfoLog(id_, length, nullptr, log.data());
    glDeleteProgram(std::exchange(id_, 0));
    throw Error("shader program " + name_ + " does not link: " + log.c_str(), ErrorKind::Failure);
  }
  checkErrors("linking shader program");
}

Program::~Program() {
  if (id_ && canDelete(context_)) glDeleteProgram(id_);
}

Program& Program::operator=(Program&& o) noexcept {
  if (this != &o) {
    if (id_ && canDelete(context_)) glDeleteProgram(id_);
    id_ = std::exchange(o.id_, 0);
    context_ = std::exchange(o.context_, 0);
    name_ = std::move(o.name_);
  }
  return *this;
}

void Program::use() const {
  if (!Context::isCurrentSerial(context_))
    throw Error("shader program " + name_ + " is used while the GL context it was made in is not current",
                ErrorKind::Failure);
  glUseProgram(id_);
}

void Program::dispatch(GLuint x, GLuint y, GLuint z, GLbitfield barrier) const {
  use();
  glDispatchCompute(x, y, z);
  if (barrier) glMemoryBarrier(barrier);
  checkErrors("compute dispatch");
}

void Program::dispatchIndirect(GLuint args, GLintptr offset, GLbitfield barrier) const {
  use();
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, args);
  glDispatchComputeIndirect(offset);
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
  if (barrier) glMemoryBarrier(barrier);
  checkErrors("indirect compute dispatch");
}

std::array<GLuint, 2> dispatchGrid(std::uint64_t groups) {
  if (groups > std::uint64_t(65535) * 65535)
    throw Error("a dispatch of " + std::to_string(groups) + " work groups: more than a 65535 x 65535 grid holds", ErrorKind::Failure);
  return {GLuint(std::min<std::uint64_t>(groups, 65535)), GLuint((groups + 65534) / 65535)};
}

}  // namespace isoatlas::gl
