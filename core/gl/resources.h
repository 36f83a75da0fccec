// RAII owners of GL objects: Buffer, Texture, Framebuffer, VertexArray, TimerQuery. Each is made in the
// current context (checked), deletes its object when destroyed and is movable, not copyable. Uses DSA
// (GL 4.5) throughout.
#pragma once
#include <epoxy/gl.h>

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/image.h"

namespace isoatlas::gl {

// The current context's serial, for a GL object about to be made (Context::current(): throws when
// none is current).
std::uint64_t contextForNewObject();
// Whether an object made in context `serial` can be deleted now: that context exists and is current.
// Otherwise the object is left to go with its context (counted by orphanedObjects()), as a GL call
// now would act on no context or on another one; debug builds say so and abort, so a test catches it.
bool canDelete(std::uint64_t serial);
int orphanedObjects();

template <void (*Delete)(GLuint)>
class Handle {
public:
  Handle() = default;
  explicit Handle(GLuint id) : id_(id), context_(contextForNewObject()) {}
  ~Handle() { release(); }
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, 0)), context_(std::exchange(o.context_, 0)) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      release();
      id_ = std::exchange(o.id_, 0);
      context_ = std::exchange(o.context_, 0);
    }
    return *this;
  }
  GLuint id() const { return id_; }

private:
  void release() {
    if (id_ && canDelete(context_)) Delete(id_);
    id_ = 0;
  }
  GLuint id_ = 0;
  std::uint64_t context_ = 0;  // the serial of the context it was made in
};

void deleteBuffer(GLuint id);
void deleteTexture(GLuint id);
void deleteFramebuffer(GLuint id);
void deleteVertexArray(GLuint id);
void deleteQuery(GLuint id);

class Buffer : public Handle<deleteBuffer> {
public:
  Buffer() = default;
  // `bytes` of storage, filled from `data` when given; usable by the GPU and readable back.
  explicit Buffer(std::size_t bytes, const void* data = nullptr);
  template <class T>
  static Buffer of(const std::vector<T>& v) { return Buffer(v.size() * sizeof(T), v.data()); }
  std::size_t bytes() const { return bytes_; }
  void upload(const void* data, std::size_t bytes, std::size_t offset = 0);
  void download(void* data, std::size_t bytes, std::size_t offset = 0) const;
  template <class T>
  std::vector<T> read(std::size_t count) const {
    std::vector<T> out(count);
    download(out.data(), count * sizeof(T));
    return out;
  }
  void fillZero();
  void fillZero(std::size_t bytes);  // the first `bytes` only (all of it if it is smaller)
  // At least `bytes` of storage, what it held kept at its start (a new buffer where it must grow).
  void growTo(std::size_t bytes);
  // At least `bytes` of storage (16 at least), its contents not kept: a new buffer only where it must
  // grow, then a quarter larger (buffers reused call after call, for work whose size changes a little).
  void reserve(std::size_t bytes);
  void bindBase(GLenum target, GLuint index) const { glBindBufferBase(target, index, id()); }
  // fillZero's way on a GPU, by a compute shader; public so that a software renderer's tests run it.
  void zeroWords(std::size_t words);

private:
  std::size_t bytes_ = 0;
};

class Texture : public Handle<deleteTexture> {
public:
  Texture() = default;
  static Texture texture2D(GLenum internalFormat, int width, int height, int levels = 1);
  static Texture texture3D(GLenum internalFormat, int width, int height, int depth);
  // A view of `buffer` as a buffer texture of `internalFormat` texels (e.g. GL_RGB32I); the buffer
  // must outlive it.
  static Texture textureBuffer(GLenum internalFormat, const Buffer& buffer);
  GLenum target() const { return target_; }
  int width() const { return size_[0]; }
  int height() const { return size_[1]; }
  int depth() const { return size_[2]; }
  // A 2D GL_R32F texture's level 0 into `out` (width x height floats, rows bottom to top), read in
  // bands of whole rows of at most `bandBytes`: GL counts a read's bytes in a GLsizei, which a
  // read of 2 GiB or more would overflow (a large phi pool is that big).
  static constexpr std::size_t kReadBandBytes = std::size_t(1) << 30;
  void readRedFloats(std::vector<float>& out, std::size_t bandBytes = kReadBandBytes) const;

private:
  Texture(GLenum target, int w, int h, int d);
  GLenum target_ = 0;
  int size_[3] = {0, 0, 0};
};

class Framebuffer : public Handle<deleteFramebuffer> {
public:
  Framebuffer() = default;
  // An RGBA8 colour target with a depth buffer, for headless rendering.
  Framebuffer(int width, int height);
  void bind() const;
  std::vector<unsigned char> readRgba() const;  // rows bottom to top, as GL stores them
  Image readImage() const;                       // RGB, rows top to bottom
  const Texture& colour() const { return colour_; }
  int width() const { return w_; }
  int height() const { return h_; }

private:
  Texture colour_, depth_;
  int w_ = 0, h_ = 0;
};

// The default framebuffer's back buffer (a window's, before it is swapped) as RGB, rows top to bottom.
Image readWindowImage(int width, int height);

class VertexArray : public Handle<deleteVertexArray> {
public:
  VertexArray();
  void bind() const { glBindVertexArray(id()); }
};

// Measures GPU time between begin() and end() with a GL_TIME_ELAPSED query.
class TimerQuery : public Handle<deleteQuery> {
public:
  TimerQuery();
  void begin() const { glBeginQuery(GL_TIME_ELAPSED, id()); }
  void end() const { glEndQuery(GL_TIME_ELAPSED); }
  double milliseconds() const;  // waits for the result
};

}  // namespace isoatlas::gl
