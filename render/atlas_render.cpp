#include "render/atlas_render.h"

#include <algorithm>
#include <chrono>
#include <tuple>

#include "core/error.h"
#include "core/gl/context.h"
#include "core/gl/program.h"
#include "kRenderShaders.h"

namespace isoatlas::render {
namespace {

// With the geometry stage (the wireframe's distances, transform feedback's output), or, for plain
// frames, straight from the evaluation stage to the fragments.
gl::ProgramSource atlasProgram(bool direct) {
  std::vector<std::string> paths = {"render/shaders/atlas.vert", "render/shaders/atlas.tesc", "render/shaders/atlas.tese"};
  if (direct) {
    paths.push_back("render/shaders/atlas_direct.frag");
    return {gl::kRenderShaders, paths, {}, {}};
  }
  paths.insert(paths.end(), {"render/shaders/atlas.geom", "render/shaders/atlas.frag"});
  return {gl::kRenderShaders, paths, {}, {"worldPosition"}};
}

// On llvmpipe every draw goes in chunks of patches:
// - with the geometry stage (the wireframe, the capture), its draw module numbers a draw's
//   tessellated vertices in 16 bits: past 65,536 vertices in one draw, triangles took earlier
//   vertices (bunny00's capture at level 8 had 62,663 distinct positions for 192,514, and was not a
//   manifold). A chunk holds at most 65,536 of the most vertices a patch can make;
// - without it, a draw slows more than linearly with the vertices it makes (bunny00's 4 x 4 grid at
//   1920 x 1080: 1.25 s a frame in one draw an instance, 0.24 s in draws of 16 patches).
constexpr std::size_t kSoftwareVertices = 65536, kSoftwareChunk = 16;
std::size_t softwareChunk(int maxTessLevel) {
  const std::size_t mostPerPatch = std::size_t(maxTessLevel + 1) * std::size_t(maxTessLevel + 1);
  return std::clamp<std::size_t>(kSoftwareVertices / mostPerPatch, 1, kSoftwareChunk);
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

// Position (RGB32F) and normal (RGB16_SNORM) textures of `w` x `h` texels.
std::pair<gl::Texture, gl::Texture> uploadImages(int w, int h, const void* positions, const void* normals) {
  const int limit = gl::Context::current().info().maxTextureSize;
  require(w <= limit && h <= limit, "the model's atlas (" + std::to_string(w) + "x" + std::to_string(h) +
                                        " texels) is larger than this GL driver's largest texture (" + std::to_string(limit) + ")");
  gl::Texture p = gl::Texture::texture2D(GL_RGB32F, w, h), n = gl::Texture::texture2D(GL_RGB16_SNORM, w, h);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(p.id(), 0, 0, 0, w, h, GL_RGB, GL_FLOAT, positions);
  glTextureSubImage2D(n.id(), 0, 0, 0, w, h, GL_RGB, GL_SHORT, normals);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  gl::checkErrors("uploading the atlas");
  return {std::move(p), std::move(n)};
}

}  // namespace

AtlasTextures::AtlasTextures(const atlas::Atlas& atlas) : layout_(atlas.layout) {
  require(layout_.width() > 0 && layout_.height() > 0, "the model has an empty atlas");
  std::tie(positions_, normals_) = uploadImages(int(layout_.width()), int(layout_.height()), atlas.positions.data(), atlas.normals.data());
  std::vector<std::int32_t> slots(layout_.charts, -1);
  if (atlas.details.empty()) {
    const float zero[3] = {0, 0, 0};
    const std::int16_t up[3] = {0, 0, 32767};
    std::tie(detailPositions_, detailNormals_) = uploadImages(1, 1, zero, up);
  } else {
    const std::uint32_t m = atlas.details.front().size;
    detailLayout_ = atlas::packCharts(std::uint32_t(atlas.details.size()), m);
    std::vector<std::array<float, 3>> positions(std::size_t(detailLayout_.width()) * detailLayout_.height());
    std::vector<atlas::Normal16> normals(positions.size());
    for (std::uint32_t k = 0; k < atlas.details.size(); ++k) {
      const atlas::DetailChart& d = atlas.details[k];
      slots[d.tile] = std::int32_t(k);
      for (std::uint32_t j = 0; j < m; ++j)
        for (std::uint32_t i = 0; i < m; ++i) {
          positions[detailLayout_.texel(k, i, j)] = d.positions[std::size_t(j) * m + i];
          normals[detailLayout_.texel(k, i, j)] = d.normals[std::size_t(j) * m + i];
        }
    }
    std::tie(detailPositions_, detailNormals_) =
        uploadImages(int(detailLayout_.width()), int(detailLayout_.height()), positions.data(), normals.data());
  }
  detailSlots_ = gl::Buffer::of(slots);
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
    : program_(&gl::Context::current().program(atlasProgram(false))),
      direct_(&gl::Context::current().program(atlasProgram(true))),
      chunk_(gl::Context::current().info().software() ? softwareChunk(gl::Context::current().info().maxTessellationLevel) : 0),
      maxTessLevel_(powerOfTwoAtMost(gl::Context::current().info().maxTessellationLevel)) {}

const gl::Program& AtlasRenderer::prepare(const Camera& camera, const Box& scene, const GpuRefinement& gpu, const DrawStyle& style,
                                          bool capturing) const {
  camera.check();
  require(gpu.halvings >= 0 && gpu.halvings <= 16, "--gpu-level must lie between 0 and 16");
  require(gpu.pixels > 0, "--gpu-pixels must be positive");
  const gl::Program& p = capturing || style.wireframe ? *program_ : *direct_;
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
  return p;
}

// Draws with the program prepare() set up (also while transform feedback is active, when the
// program may not change).
void AtlasRenderer::drawItems(const gl::Program& p, const std::vector<DrawItem>& items) const {
  const std::size_t chunk = chunk_ ? chunk_ : ~std::size_t(0);  // every program: see softwareChunk
  for (const DrawItem& item : items) {
    if (item.patches->count() == 0) continue;
    const float model[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, float(item.offset.x), float(item.offset.y), float(item.offset.z), 1};
    glUniformMatrix4fv(p.uniform("model"), 1, GL_FALSE, model);
    const atlas::AtlasLayout &charts = item.atlas->layout(), &details = item.atlas->detailLayout();
    glUniform1ui(p.uniform("chartSize"), charts.chartSize);
    glUniform1ui(p.uniform("atlasColumns"), charts.columns);
    glUniform1ui(p.uniform("detailRatio"), details.charts ? (details.chartSize - 1) / (charts.chartSize - 1) : 1);
    glUniform1ui(p.uniform("detailSize"), details.chartSize);
    glUniform1ui(p.uniform("detailColumns"), std::max(details.columns, 1u));
    glBindTextureUnit(0, item.atlas->positions().id());
    glBindTextureUnit(1, item.atlas->normals().id());
    glBindTextureUnit(2, item.atlas->detailPositions().id());
    glBindTextureUnit(3, item.atlas->detailNormals().id());
    item.patches->buffer().bindBase(GL_SHADER_STORAGE_BUFFER, 0);
    item.atlas->detailSlots().bindBase(GL_SHADER_STORAGE_BUFFER, 1);
    for (std::size_t first = 0; first < item.patches->count(); first += chunk)
      glDrawArrays(GL_PATCHES, gl::glSize(first, "drawing the atlas's patches"), gl::glSize(std::min(chunk, item.patches->count() - first), "drawing the atlas's patches"));
  }
  gl::checkErrors("drawing the atlas");
}

FrameFigures drawMeasured(const gl::Framebuffer& target, const Vec3& background, const std::function<void()>& draw) {
  target.bind();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glClearColor(float(background.x), float(background.y), float(background.z), 1);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  FrameFigures f;
  gl::TimerQuery timer;
  Query primitives(GL_PRIMITIVES_GENERATED);
  const auto start = std::chrono::steady_clock::now();
  timer.begin();
  draw();
  timer.end();
  f.triangles = primitives.end();
  glFinish();
  // A software rasteriser runs the draw at the finish, outside the timer query: take the longer.
  f.gpuMs = std::max(timer.milliseconds(), std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  return f;
}

Mesh captureTriangles(const std::vector<CapturePass>& passes) {
  gl::Framebuffer fbo(8, 8);  // EGL surfaceless has no default framebuffer, even with rasterizer discard
  fbo.bind();
  glEnable(GL_RASTERIZER_DISCARD);
  std::vector<std::uint64_t> counts;
  for (const CapturePass& pass : passes) {
    pass.program->use();
    Query counting(GL_PRIMITIVES_GENERATED);
    pass.draw();
    counts.push_back(counting.end());
  }
  std::uint64_t triangles = 0;
  for (const std::uint64_t c : counts) triangles += c;
  Mesh mesh;
  if (triangles > 0) {
    const std::size_t bytesPerTriangle = 9 * sizeof(float);
    gl::Buffer captured(triangles * bytesPerTriangle);
    std::uint64_t at = 0;
    for (std::size_t k = 0; k < passes.size(); ++k) {
      if (counts[k] == 0) continue;
      glBindBufferRange(GL_TRANSFORM_FEEDBACK_BUFFER, 0, captured.id(), GLintptr(at * bytesPerTriangle), GLsizeiptr(counts[k] * bytesPerTriangle));
      passes[k].program->use();
      Query written(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN);
      glBeginTransformFeedback(GL_TRIANGLES);
      passes[k].draw();
      glEndTransformFeedback();
      const std::uint64_t got = written.end();
      if (got != counts[k])
        throw Error("transform feedback kept " + std::to_string(got) + " of " + std::to_string(counts[k]) + " triangles", ErrorKind::Failure);
      at += got;
    }
    glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, 0);
    const std::vector<float> data = captured.read<float>(triangles * 9);
    mesh.positions.reserve(triangles * 3);
    for (std::size_t i = 0; i < triangles * 3; ++i) mesh.positions.push_back({data[3 * i], data[3 * i + 1], data[3 * i + 2]});
    for (std::uint32_t t = 0; t < triangles; ++t) mesh.addFace({3 * t, 3 * t + 1, 3 * t + 2});
  }
  glDisable(GL_RASTERIZER_DISCARD);
  gl::checkErrors("capturing the tessellation");
  return mesh;
}

FrameFigures AtlasRenderer::draw(const std::vector<DrawItem>& items, const Camera& camera, const Box& scene,
                                 const GpuRefinement& gpu, const DrawStyle& style, const gl::Framebuffer& target) const {
  FrameFigures f = drawMeasured(target, style.background, [&] { drawItems(prepare(camera, scene, gpu, style, false), items); });
  for (const DrawItem& item : items) f.patches += item.patches->count();
  return f;
}

Mesh AtlasRenderer::capture(const std::vector<DrawItem>& items, const Camera& camera, const Box& scene,
                            const GpuRefinement& gpu) const {
  const gl::Program& p = prepare(camera, scene, gpu, {}, true);
  return captureTriangles({{&p, [&] { drawItems(p, items); }}});
}

}  // namespace isoatlas::render
