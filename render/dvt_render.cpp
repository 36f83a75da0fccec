#include "render/dvt_render.h"

#include <cmath>
#include <vector>

#include "core/gl/program.h"
#include "kRenderShaders.h"
#include "edit/dvt/tree_rules.h"

namespace isoatlas::render {
namespace dvt = edit::dvt;
namespace {

// The viewer's shader files and the tree's, in one table (dvt_tree.glsl includes tree_layout.glsl).
const gl::EmbeddedShader* dvtRenderShaders() {
  static const std::vector<gl::EmbeddedShader> table = gl::joinShaderTables({gl::kRenderShaders, dvt::treeShaderFiles()});
  return table.data();
}

gl::ProgramSource source(const char* vert, const char* frag) {
  return {dvtRenderShaders(), {vert, frag}, dvt::ruleDefines(), {}};
}

// The world box around the tree's whole frame.
Box frameBox(const dvt::TreeFrame& f) {
  std::vector<Vec3> corners;
  const double side = double(f.voxelsPerAxis()) - 0.5;
  for (int k = 0; k < 8; ++k) {
    const Vec3 index{k & 1 ? side : -0.5, k & 2 ? side : -0.5, k & 4 ? side : -0.5};
    corners.push_back(f.indexToWorld(index));
  }
  return boundingBox(corners);
}

}  // namespace

DvtRenderer::DvtRenderer()
    : cubes_(gl::Context::current().program(source("render/shaders/dvt_cubes.vert", "render/shaders/dvt_cubes.frag"))),
      rayCast_(gl::Context::current().program({dvtRenderShaders(), {"render/shaders/dvt_raycast.comp"}, dvt::ruleDefines(), {}})) {}

void DvtRenderer::draw(const dvt::GpuTreeBuffers& buffers, std::uint64_t nodeCount, const dvt::TreeFrame& frame, const DvtView& view) {
  const Camera& cam = view.camera;
  cam.check();
  const auto [near, far] = depthRange(cam, frameBox(frame));
  const Mat4 vp = cam.viewProjection(near, far), toWorld = gridToWorld(frame.direction, frame.spacing, frame.origin);
  const auto normals = normalMatrix(toWorld);
  glViewport(0, 0, cam.width, cam.height);
  glClearColor(float(view.background.x), float(view.background.y), float(view.background.z), 1);
  glClearDepth(1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  // Rays find their own first hit; the cubes need the depth test.
  if (view.mode == DvtRenderMode::Cubes) glEnable(GL_DEPTH_TEST);
  else glDisable(GL_DEPTH_TEST);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffers.pointers);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buffers.cells);
  const gl::Program& p = view.mode == DvtRenderMode::Cubes ? cubes_ : rayCast_;
  p.use();
  glUniformMatrix4fv(p.uniform("viewProjection"), 1, GL_FALSE, vp.data());
  glUniformMatrix4fv(p.uniform("indexToWorld"), 1, GL_FALSE, toWorld.data());
  glUniformMatrix3fv(p.uniform("normalToWorld"), 1, GL_FALSE, normals.data());
  glUniform1i(p.uniform("voxelSplits"), frame.voxelSplits);
  glUniform3f(p.uniform("eye"), float(cam.eye.x), float(cam.eye.y), float(cam.eye.z));
  glUniform3f(p.uniform("colour"), float(view.colour.x), float(view.colour.y), float(view.colour.z));
  glUniform1i(p.uniform("colourByChart"), 0);
  if (view.mode == DvtRenderMode::Cubes) {
    vao_.bind();
    glDrawArraysInstanced(GL_TRIANGLES, 0, 36, gl::glSize(nodeCount, "drawing the tree's nodes"));
  } else {
    std::vector<float> radius(dvt::kMaxDepth + 1);
    for (std::uint32_t d = 0; d < radius.size(); ++d) radius[d] = float(frame.radius(d));
    glUniformMatrix4fv(p.uniform("inverseViewProjection"), 1, GL_FALSE, inverse(vp).data());
    glUniformMatrix4fv(p.uniform("worldToIndex"), 1, GL_FALSE, inverse(toWorld).data());
    glUniform3f(p.uniform("background"), float(view.background.x), float(view.background.y), float(view.background.z));
    glUniform2f(p.uniform("viewportSize"), float(cam.width), float(cam.height));
    glUniform1fv(p.uniform("radius"), GLsizei(radius.size()), radius.data());
    // Into a picture of our own, then copied into the bound framebuffer.
    GLint target = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target);
    if (!rays_ || rays_->width() != cam.width || rays_->height() != cam.height) rays_ = std::make_unique<gl::Framebuffer>(cam.width, cam.height);
    glBindImageTexture(0, rays_->colour().id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    p.dispatch(GLuint(cam.width + 7) / 8, GLuint(cam.height + 7) / 8, 1, GL_FRAMEBUFFER_BARRIER_BIT);
    glBlitNamedFramebuffer(rays_->id(), GLuint(target), 0, 0, cam.width, cam.height, 0, 0, cam.width, cam.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
}

Box insideBounds(const dvt::VolumeTree& tree) {
  std::vector<Vec3> corners;
  for (std::size_t n = 0; n < tree.nodeCount(); ++n) {
    if (!tree.pointers[n].leaf() || tree.pointers[n].value <= 0) continue;
    const dvt::Cell c = tree.cell(n);
    const Vec3 centre = tree.frame.centreIndex(c), s = tree.frame.cellVoxels(c.depth);
    for (int k = 0; k < 8; ++k) {
      const Vec3 index{centre.x + (k & 1 ? 0.5 : -0.5) * s.x, centre.y + (k & 2 ? 0.5 : -0.5) * s.y, centre.z + (k & 4 ? 0.5 : -0.5) * s.z};
      corners.push_back(tree.frame.indexToWorld(index));
    }
  }
  return corners.empty() ? frameBox(tree.frame) : boundingBox(corners);
}

Image renderTree(const dvt::GpuTreeBuffers& buffers, std::uint64_t nodeCount, const dvt::TreeFrame& frame, const DvtView& view) {
  const gl::Framebuffer fb(view.camera.width, view.camera.height);
  fb.bind();
  DvtRenderer().draw(buffers, nodeCount, frame, view);
  glFinish();
  return fb.readImage();
}

Image renderTree(const dvt::VolumeTree& tree, const DvtView& view) {
  gl::Context::current();
  const gl::Buffer pointers = gl::Buffer::of(tree.pointers), cells = gl::Buffer::of(tree.cells);
  return renderTree({pointers.id(), cells.id()}, tree.nodeCount(), tree.frame, view);
}

}  // namespace isoatlas::render
