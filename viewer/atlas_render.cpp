#include "viewer/atlas_render.h"

#include <algorithm>
#include <chrono>

#include "core/error.h"
#include "core/gl/context.h"
#include "core/gl/program.h"
#include "kViewerShaders.h"

namespace isoatlas::viewer {
namespace {

const gl::ProgramSource& atlasProgram() {
  static const gl::ProgramSource source{
      gl::kViewerShaders,
      {"viewer/shaders/atlas.vert", "viewer/shaders/atlas.tesc", "viewer/shaders/atlas.tese", "viewer/shaders/atlas.geom",
       "viewer/shaders/atlas.frag"},
      {},
      {"worldPosition"}};
  return source;
}

// The largest power of two the driver's tessellator accepts (GL 4.5 guarantees 64).
unsigned powerOfTwoAtMost(int limit) {
  unsigned p = 1;
  while (int(p * 2) <= limit) p *= 2;
  return p;
}

// A GL query of `target` over a scope; result() waits for it.
class Query : public gl::Handle<gl::deleteQuery> {
public:
  explicit Query(GLenum target) : gl::Handle<gl::deleteQuery>(make(target)), target_(target) { glBeginQuery(target_, id()); }
  std::uint64_t end() {
    glEndQuery(target_);
    GLuint64 value = 0;
    glGetQueryObjectui64v(id(), GL_QUERY_RESULT, &value);
    return value;
  }

private:
  static GLuint make(GLenum target) {
    GLuint q = 0;
    glCreateQueries(target, 1, &q);
    return q;
  }
  GLenum target_;
};

}  // namespace

AtlasTextures::AtlasTextures(const atlas::Atlas& atlas) : layout_(atlas.layout) {
  const int limit = gl::Context::current().info().maxTextureSize;
  const int w = int(layout_.width()), h = int(layout_.height());
  require(w > 0 && h > 0, "the model has an empty atlas");
  require(w <= limit && h <= limit, "the model's atlas (" + std::to_string(w) + "x" + std::to_string(h) +
                                        " texels) is larger than this GL driver's largest texture (" + std::to_string(limit) + ")");
  positions_ = gl::Texture::texture2D(GL_RGB32F, w, h);
  normals_ = gl::Texture::texture2D(GL_RGB16_SNORM, w, h);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(positions_.id(), 0, 0, 0, w, h, GL_RGB, GL_FLOAT, atlas.positions.data());
  glTextureSubImage2D(normals_.id(), 0, 0, 0, w, h, GL_RGB, GL_SHORT, atlas.normals.data());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  gl::checkErrors("uploading the atlas");
}

std::size_t PatchBuffer::update(const std::vector<GpuPatch>& patches) {
  const std::size_t bytes = std::max<std::size_t>(patches.size(), 1) * sizeof(GpuPatch);
  if (bytes > buffer_.bytes()) {
    buffer_ = gl::Buffer(bytes + bytes / 2);
    buffer_.upload(patches.data(), patches.size() * sizeof(GpuPatch));
    held_ = patches;
    return patches.size() * sizeof(GpuPatch);
  }
  std::size_t first = 0;
  while (first < patches.size() && first < held_.size() && patches[first] == held_[first]) ++first;
  std::size_t last = patches.size();
  if (patches.size() == held_.size())
    while (last > first && patches[last - 1] == held_[last - 1]) --last;
  if (last > first) buffer_.upload(patches.data() + first, (last - first) * sizeof(GpuPatch), first * sizeof(GpuPatch));
  held_ = patches;
  return (last - first) * sizeof(GpuPatch);
}

AtlasRenderer::AtlasRenderer()
    : program_(&gl::Context::current().program(atlasProgram())),
      maxTessLevel_(powerOfTwoAtMost(gl::Context::current().info().maxTessellationLevel)) {}

void AtlasRenderer::prepare(const Camera& camera, const Box& scene, const GpuRefinement& gpu, const DrawStyle& style) const {
  camera.check();
  require(gpu.halvings >= 0 && gpu.halvings <= 16, "--gpu-level must lie between 0 and 16");
  require(gpu.pixels > 0, "--gpu-pixels must be positive");
  const gl::Program& p = *program_;
  p.use();
  const auto range = depthRange(camera, scene);
  const auto vp = camera.viewProjection(range[0], range[1]);
  glUniformMatrix4fv(p.uniform("viewProjection"), 1, GL_FALSE, vp.data());
  glUniform2f(p.uniform("viewport"), float(camera.width), float(camera.height));
  glUniform1f(p.uniform("nearPlane"), float(range[0]));
  glUniform1i(p.uniform("gpuMode"), gpu.mode == GpuRefinement::Mode::Level ? 0 : 1);
  glUniform1ui(p.uniform("gpuLevel"), unsigned(gpu.halvings));
  glUniform1f(p.uniform("gpuPixels"), float(gpu.pixels));
  glUniform1ui(p.uniform("maxTessLevel"), maxTessLevel_);
  glUniform3f(p.uniform("eye"), float(camera.eye.x), float(camera.eye.y), float(camera.eye.z));
  glUniform3f(p.uniform("colour"), float(style.colour.x), float(style.colour.y), float(style.colour.z));
  glUniform1i(p.uniform("colourByChart"), style.colourByChart);
  glUniform1i(p.uniform("wireframe"), style.wireframe);
  glPatchParameteri(GL_PATCH_VERTICES, 1);
  vao_.bind();
}

// Draws with the program prepare() set up (also while transform feedback is active, when the
// program may not change).
void AtlasRenderer::drawItems(const std::vector<DrawItem>& items) const {
  const gl::Program& p = *program_;
  for (const DrawItem& item : items) {
    if (item.patches->count() == 0) continue;
    const float model[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, float(item.offset.x), float(item.offset.y), float(item.offset.z), 1};
    glUniformMatrix4fv(p.uniform("model"), 1, GL_FALSE, model);
    glUniform1ui(p.uniform("chartSize"), item.atlas->layout().chartSize);
    glUniform1ui(p.uniform("atlasColumns"), item.atlas->layout().columns);
    glBindTextureUnit(0, item.atlas->positions().id());
    glBindTextureUnit(1, item.atlas->normals().id());
    item.patches->buffer().bindBase(GL_SHADER_STORAGE_BUFFER, 0);
    glDrawArrays(GL_PATCHES, 0, GLsizei(item.patches->count()));
  }
  gl::checkErrors("drawing the atlas");
}

FrameFigures AtlasRenderer::draw(const std::vector<DrawItem>& items, const Camera& camera, const Box& scene,
                                 const GpuRefinement& gpu, const DrawStyle& style, const gl::Framebuffer& target) const {
  target.bind();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glClearColor(float(style.background.x), float(style.background.y), float(style.background.z), 1);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  FrameFigures f;
  for (const DrawItem& item : items) f.patches += item.patches->count();
  gl::TimerQuery timer;
  Query primitives(GL_PRIMITIVES_GENERATED);
  prepare(camera, scene, gpu, style);
  const auto start = std::chrono::steady_clock::now();
  timer.begin();
  drawItems(items);
  timer.end();
  f.triangles = primitives.end();
  glFinish();
  // A software rasteriser runs the draw at the finish, outside the timer query: take the longer.
  f.gpuMs = std::max(timer.milliseconds(), std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  return f;
}

Mesh AtlasRenderer::capture(const std::vector<DrawItem>& items, const Camera& camera, const Box& scene,
                            const GpuRefinement& gpu) const {
  gl::Framebuffer fbo(8, 8);  // EGL surfaceless has no default framebuffer, even with rasterizer discard
  fbo.bind();
  glEnable(GL_RASTERIZER_DISCARD);
  std::uint64_t triangles = 0;
  prepare(camera, scene, gpu, {});
  {
    Query counting(GL_PRIMITIVES_GENERATED);
    drawItems(items);
    triangles = counting.end();
  }
  Mesh mesh;
  if (triangles > 0) {
    gl::Buffer captured(triangles * 9 * sizeof(float));
    glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, captured.id());
    Query written(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN);
    glBeginTransformFeedback(GL_TRIANGLES);
    drawItems(items);
    glEndTransformFeedback();
    const std::uint64_t got = written.end();
    glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, 0);
    if (got != triangles) throw Error("transform feedback kept " + std::to_string(got) + " of " + std::to_string(triangles) + " triangles", ErrorKind::Failure);
    const std::vector<float> data = captured.read<float>(triangles * 9);
    mesh.positions.reserve(triangles * 3);
    for (std::size_t i = 0; i < triangles * 3; ++i) mesh.positions.push_back({data[3 * i], data[3 * i + 1], data[3 * i + 2]});
    for (std::uint32_t t = 0; t < triangles; ++t) mesh.addFace({3 * t, 3 * t + 1, 3 * t + 2});
  }
  glDisable(GL_RASTERIZER_DISCARD);
  gl::checkErrors("capturing the tessellation");
  return mesh;
}

}  // namespace isoatlas::viewer
