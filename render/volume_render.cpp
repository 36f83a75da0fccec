#include "render/volume_render.h"

#include "core/error.h"
#include "kRenderShaders.h"
#include "levelset/speed.h"

namespace isoatlas::render {
namespace {

const gl::Program& rayCaster(gl::Context& context, int pageSize) {
  static const std::vector<gl::EmbeddedShader> shaders = gl::joinShaderTables({gl::kRenderShaders, levelset::levelsetShaderFiles()});
  return context.compute(shaders.data(), "render/shaders/volume_raycast.comp",
                         {{"PAGE_SIZE", std::to_string(pageSize)}, {"PHI_CLAMP", gl::glslFloat(levelset::kClamp)}});
}

}  // namespace

Box gridBounds(const Volume& v) {
  std::vector<Vec3> corners;
  for (int k = 0; k < 8; ++k)
    corners.push_back(v.indexToWorld({k & 1 ? double(v.dims[0]) - 0.5 : -0.5, k & 2 ? double(v.dims[1]) - 0.5 : -0.5,
                                      k & 4 ? double(v.dims[2]) - 0.5 : -0.5}));
  return boundingBox(corners);
}

VolumeRenderer::VolumeRenderer() { gl::Context::current(); }  // throws now, not at the first draw, when none is current

void VolumeRenderer::setSource(const Volume& source) {
  geometry_ = source.sameGeometry(ScalarType::Float32);
  geometry_.data.clear();
  const std::vector<float> values = source.toFloat();
  source_ = gl::Texture::texture3D(GL_R32F, int(source.dims[0]), int(source.dims[1]), int(source.dims[2]));
  glTextureSubImage3D(source_.id(), 0, 0, 0, 0, int(source.dims[0]), int(source.dims[1]), int(source.dims[2]), GL_RED, GL_FLOAT,
                      values.data());
  glTextureParameteri(source_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(source_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R}) glTextureParameteri(source_.id(), wrap, GL_CLAMP_TO_EDGE);
}

void VolumeRenderer::draw(const levelset::PagedPhiGpu& phi, const VolumeRenderView& view) {
  if (source_.id() == 0) throw Error("VolumeRenderer: no scan was given (setSource)", ErrorKind::Failure);
  const Camera& cam = view.camera;
  cam.check();
  const auto [near, far] = depthRange(cam, gridBounds(geometry_));
  const Mat4 vp = cam.viewProjection(near, far), toWorld = gridToWorld(geometry_.direction, geometry_.spacing, geometry_.origin);
  const Mat4 toIndex = inverse(toWorld);
  const gl::Program& p = rayCaster(gl::Context::current(), phi.pageSize());
  p.use();
  phi.bindData(0, 0);
  phi.setUniforms(p);
  glBindTextureUnit(0, source_.id());
  glUniformMatrix4fv(p.uniform("inverseViewProjection"), 1, GL_FALSE, inverse(vp).data());
  glUniformMatrix4fv(p.uniform("worldToIndex"), 1, GL_FALSE, toIndex.data());
  glUniformMatrix4fv(p.uniform("indexToWorld"), 1, GL_FALSE, toWorld.data());
  glUniformMatrix3fv(p.uniform("normalToWorld"), 1, GL_FALSE, normalMatrix(toWorld).data());
  glUniform3i(p.uniform("dims"), int(geometry_.dims[0]), int(geometry_.dims[1]), int(geometry_.dims[2]));
  glUniform2f(p.uniform("viewportSize"), float(cam.width), float(cam.height));
  glUniform3f(p.uniform("background"), float(view.background.x), float(view.background.y), float(view.background.z));
  glUniform3f(p.uniform("colour"), float(view.colour.x), float(view.colour.y), float(view.colour.z));
  glUniform3f(p.uniform("eye"), float(cam.eye.x), float(cam.eye.y), float(cam.eye.z));
  glUniform1i(p.uniform("colourByChart"), 0);
  glUniform2f(p.uniform("window"), float(view.window.low), float(view.window.high));
  glUniform1f(p.uniform("opacity"), float(view.opacity));
  glUniform1i(p.uniform("showScan"), view.scan);
  glUniform1i(p.uniform("insideOnly"), view.insideOnly);
  glUniform1i(p.uniform("showSurface"), view.surface);
  glUniform1i(p.uniform("clipOn"), view.clip.has_value());
  if (view.clip) {
    // The plane in index space: a normal transforms by the transpose of the index-to-world matrix.
    const Vec3 n = view.clip->normal, q = geometry_.worldToIndex(view.clip->point);
    Vec3 ni;
    for (int c = 0; c < 3; ++c) ni[c] = toWorld[std::size_t(4 * c)] * n.x + toWorld[std::size_t(4 * c + 1)] * n.y + toWorld[std::size_t(4 * c + 2)] * n.z;
    glUniform4f(p.uniform("clipPlane"), float(ni.x), float(ni.y), float(ni.z), float(-dot(ni, q)));
  }
  GLint target = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target);
  if (!rays_ || rays_->width() != cam.width || rays_->height() != cam.height) rays_ = std::make_unique<gl::Framebuffer>(cam.width, cam.height);
  glBindImageTexture(1, rays_->colour().id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
  p.dispatch(GLuint(cam.width + 7) / 8, GLuint(cam.height + 7) / 8, 1, GL_FRAMEBUFFER_BARRIER_BIT);
  glBlitNamedFramebuffer(rays_->id(), GLuint(target), 0, 0, cam.width, cam.height, 0, 0, cam.width, cam.height, GL_COLOR_BUFFER_BIT,
                         GL_NEAREST);
}

Image renderVolume(const Volume& source, const levelset::LevelSet& levelSet, const VolumeRenderView& view) {
  VolumeRenderer renderer;
  renderer.setSource(source);
  const levelset::PagedPhiGpu phi(levelSet);
  gl::Framebuffer target(view.camera.width, view.camera.height);
  target.bind();
  renderer.draw(phi, view);
  return target.readImage();
}

}  // namespace isoatlas::render
