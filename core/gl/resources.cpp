#include "core/gl/resources.h"

#include "core/error.h"
#include "core/gl/context.h"
#include "core/gl/program.h"
#include "kGlShaders.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace isoatlas::gl {

namespace {
std::atomic<int> g_orphans{0};
}  // namespace

std::uint64_t contextForNewObject() { return Context::current().serial(); }

bool canDelete(std::uint64_t serial) {
  if (Context::isCurrentSerial(serial)) return true;
  ++g_orphans;
#ifndef NDEBUG
  std::fprintf(stderr, "isoatlas: a GL object is destroyed while the context it was made in is not current\n");
  std::abort();
#endif
  return false;
}

int orphanedObjects() { return g_orphans; }

void deleteBuffer(GLuint id) { glDeleteBuffers(1, &id); }
void deleteTexture(GLuint id) { glDeleteTextures(1, &id); }
void deleteFramebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
void deleteVertexArray(GLuint id) { glDeleteVertexArrays(1, &id); }
void deleteQuery(GLuint id) { glDeleteQueries(1, &id); }

namespace {
GLuint create(void (*fn)(GLsizei, GLuint*)) {
  contextForNewObject();
  GLuint id = 0;
  fn(1, &id);
  return id;
}
}  // namespace

Buffer::Buffer(std::size_t bytes, const void* data) : Handle(create(glCreateBuffers)), bytes_(bytes) {
  glNamedBufferStorage(id(), GLsizeiptr(bytes ? bytes : 4), data, GL_DYNAMIC_STORAGE_BIT);
  checkErrors("allocating a GL buffer");
}

void Buffer::upload(const void* data, std::size_t bytes, std::size_t offset) {
  require(offset + bytes <= bytes_, "GL buffer upload past its end");
  glNamedBufferSubData(id(), GLintptr(offset), GLsizeiptr(bytes), data);
}

void Buffer::download(void* data, std::size_t bytes, std::size_t offset) const {
  require(offset + bytes <= bytes_, "GL buffer download past its end");
  glGetNamedBufferSubData(id(), GLintptr(offset), GLsizeiptr(bytes), data);
  checkErrors("reading a GL buffer back");
}

// On a GPU by a compute shader's stores, not glClearBufferSubData: on an NVIDIA H100 the driver's clear
// ran at 8 GB/s by bytes and 32 GB/s by words, far below the card's memory (bench/RESULTS.md, "On a
// real GPU"). On a software renderer by the driver's clear by words, which is faster there. The
// caller's program is restored and the fill's binding point (the last, which no algorithm binds) is
// left unbound, so a caller's state holds.
void Buffer::growTo(std::size_t bytes) {
  if (bytes <= bytes_ && id() != 0) return;
  Buffer grown(bytes);
  if (id() != 0 && bytes_ > 0) glCopyNamedBufferSubData(id(), grown.id(), 0, 0, GLsizeiptr(bytes_));
  *this = std::move(grown);
}

void Buffer::reserve(std::size_t bytes) {
  if (bytes <= bytes_ && id() != 0) return;
  *this = Buffer(std::max<std::size_t>(id() == 0 ? bytes : bytes + bytes / 4, 16));
}

void Buffer::fillZero() { fillZero(bytes_); }

void Buffer::fillZero(std::size_t bytes) {
  bytes = std::min(bytes, bytes_);
  if (bytes == 0) return;
  if (bytes_ % 4 != 0) {  // words rounded up would pass the end: by bytes
    glClearNamedBufferSubData(id(), GL_R8UI, 0, GLsizeiptr(bytes), GL_RED_INTEGER, GL_UNSIGNED_BYTE, nullptr);
    return;
  }
  const std::size_t words = (bytes + 3) / 4;
  if (Context::current().info().software()) {
    glClearNamedBufferSubData(id(), GL_R32UI, 0, GLsizeiptr(words * 4), GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    return;
  }
  zeroWords(words);
}

void Buffer::zeroWords(std::size_t words) {
  require(words * 4 <= bytes_ && words <= 0xffffffffu, "GL buffer zeroed past its end");
  GLint bindings = 0, previous = 0;
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &bindings);
  glGetIntegerv(GL_CURRENT_PROGRAM, &previous);
  const GLuint binding = GLuint(bindings - 1);
  const Program& fill = Context::current().compute(kGlShaders, "core/gl/shaders/fill_zero.comp",
                                                   {{"FILL_BINDING", std::to_string(binding)}});
  bindBase(GL_SHADER_STORAGE_BUFFER, binding);
  fill.use();
  glUniform1ui(fill.uniform("count"), GLuint(words));
  const auto [gx, gy] = dispatchGrid((words + 1023) / 1024);  // 256 invocations of 4 words a group
  fill.dispatch(gx, gy, 1, GL_ALL_BARRIER_BITS);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, 0);
  glUseProgram(GLuint(previous));
}

Texture::Texture(GLenum target, int w, int h, int d) : target_(target), size_{w, h, d} {
  contextForNewObject();
  GLuint tex = 0;
  glCreateTextures(target, 1, &tex);
  static_cast<Handle&>(*this) = Handle(tex);
}

Texture Texture::textureBuffer(GLenum internalFormat, const Buffer& buffer) {
  Texture t(GL_TEXTURE_BUFFER, int(buffer.bytes()), 1, 1);
  glTextureBuffer(t.id(), internalFormat, buffer.id());
  checkErrors("making a buffer texture");
  return t;
}

Texture Texture::texture2D(GLenum internalFormat, int width, int height, int levels) {
  Texture t(GL_TEXTURE_2D, width, height, 1);
  glTextureStorage2D(t.id(), levels, internalFormat, width, height);
  glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
  glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(t.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  checkErrors("allocating a 2D texture");
  return t;
}

void Texture::readRedFloats(std::vector<float>& out, std::size_t bandBytes) const {
  const std::size_t rowBytes = std::size_t(width()) * sizeof(float);
  out.resize(std::size_t(width()) * std::size_t(height()));
  const int rows = int(std::clamp<std::size_t>(bandBytes / std::max<std::size_t>(rowBytes, 1), 1, std::size_t(std::max(height(), 1))));
  for (int y = 0; y < height(); y += rows) {
    const int band = std::min(rows, height() - y);
    glGetTextureSubImage(id(), 0, 0, y, 0, width(), band, 1, GL_RED, GL_FLOAT, glSize(rowBytes * std::size_t(band), "reading a float texture"),
                         out.data() + std::size_t(y) * std::size_t(width()));
  }
  checkErrors("reading a float texture");
}

Texture Texture::texture3D(GLenum internalFormat, int width, int height, int depth) {
  Texture t(GL_TEXTURE_3D, width, height, depth);
  glTextureStorage3D(t.id(), 1, internalFormat, width, height, depth);
  glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glTextureParameteri(t.id(), wrap, GL_CLAMP_TO_EDGE);
  checkErrors("allocating a 3D texture");
  return t;
}

Framebuffer::Framebuffer(int width, int height)
    : Handle(create(glCreateFramebuffers)), colour_(Texture::texture2D(GL_RGBA8, width, height)),
      depth_(Texture::texture2D(GL_DEPTH_COMPONENT32F, width, height)), w_(width), h_(height) {
  glNamedFramebufferTexture(id(), GL_COLOR_ATTACHMENT0, colour_.id(), 0);
  glNamedFramebufferTexture(id(), GL_DEPTH_ATTACHMENT, depth_.id(), 0);
  if (glCheckNamedFramebufferStatus(id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw Error("the GL driver rejected a " + std::to_string(width) + "x" + std::to_string(height) + " framebuffer",
                ErrorKind::Failure);
}

namespace {
// GL's RGBA rows, bottom to top, as an RGB image with rows top to bottom.
Image imageOfRows(const std::vector<unsigned char>& rgba, int w, int h) {
  Image image(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        image.at(x, y)[c] = rgba[(std::size_t(h - 1 - y) * std::size_t(w) + std::size_t(x)) * 4 + std::size_t(c)];
  return image;
}
}  // namespace

Image Framebuffer::readImage() const { return imageOfRows(readRgba(), w_, h_); }

Image readWindowImage(int width, int height) {
  std::vector<unsigned char> rgba(std::size_t(width) * std::size_t(height) * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  checkErrors("reading the window");
  return imageOfRows(rgba, width, height);
}

void Framebuffer::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, id());
  glViewport(0, 0, w_, h_);
}

std::vector<unsigned char> Framebuffer::readRgba() const {
  std::vector<unsigned char> pixels(std::size_t(w_) * h_ * 4);
  glNamedFramebufferReadBuffer(id(), GL_COLOR_ATTACHMENT0);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, id());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w_, h_, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  checkErrors("reading the framebuffer");
  return pixels;
}

VertexArray::VertexArray() : Handle(create(glCreateVertexArrays)) {}

TimerQuery::TimerQuery() {
  contextForNewObject();
  GLuint id = 0;
  glCreateQueries(GL_TIME_ELAPSED, 1, &id);
  static_cast<Handle&>(*this) = Handle(id);
}

double TimerQuery::milliseconds() const {
  GLuint64 ns = 0;
  glGetQueryObjectui64v(id(), GL_QUERY_RESULT, &ns);
  return double(ns) * 1e-6;
}

}  // namespace isoatlas::gl
