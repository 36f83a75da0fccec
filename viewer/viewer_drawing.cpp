// The window's views left of the controls: in segment mode the three slices above the 3D view (the
// volume rendering from the pages, or the extracted surface), else the model or the tree.
#include "viewer/viewer_state.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cstdint>

#include "extract/extract_surface.h"
#include "render/mesh_render.h"

namespace isoatlas::viewer::window {

namespace {

// The background alone, where there is no surface yet.
Image surfacePictureOfNothing(int width, int height) {
  Image blank(width, height, 3);
  std::fill(blank.pixels.begin(), blank.pixels.end(), std::uint8_t(255));
  return blank;
}

}  // namespace

Image Viewer::surfacePicture(int width, int height) {
  SegmentationSession& session = *segment_->session;
  render::MeshRenderOptions o{.width = width, .height = height, .viewDirection = segment_->orbit.direction() * -1.0};
  if (session.activePages() == 0) return surfacePictureOfNothing(width, height);  // nothing segmented yet
  const levelset::LevelSet& ls = session.levelSet();
  if (backend_ == levelset::Backend::Gpu && ls.phiPoolTexture() != 0) {  // marched and drawn on the GPU, never read back
    if (!segment_->marching) segment_->marching = std::make_unique<extract::GpuMarchingCubes>();
    const extract::GpuSurface surface = extract::marchLevelSetOnGpu(ls, *segment_->marching);
    if (surface.triangleCount == 0) return surfacePictureOfNothing(width, height);
    render::GpuMeshView view{surface.vertexBuffer, surface.indexBuffer, surface.triangleCount};
    render::placeInVolume(view, ls.geometry(), surface.voxelBox);
    return render::renderMesh(view, o);
  }
  const Mesh surface = extract::extractLevelSet(ls, {.backend = backend_});
  return render::renderMesh(surface, o);
}

void Viewer::drawSegment(int width, int height) {
  SegmentView& s = *segment_;
  const int viewWidth = width - kPanelWidth;
  const int n = slicePanelSize(width, height);
  const std::uint64_t version = s.session->version();
  if (s.slicesDirty || version != s.slicesVersion || n != s.panelSize) {
    render::SliceOptions o{.panelSize = n, .window = s.window, .crosshair = s.crosshair};
    if (s.stroke) o.mask = &s.stroke->preview();  // the stroke so far, tinted over the segmentation's contour
    if (s.contour) o.phi = s.session->phi();
    const levelset::SpeedParams params = s.session->params();
    if (s.speed) o.speed = &params;
    s.slices.set(render::renderSlices(s.session->source(), s.point, o));
    s.slicesDirty = false, s.slicesVersion = version, s.panelSize = n;
  }
  s.slices.blit(0, 0, height);
  // The 3D view below the slices.
  const int w3 = std::max(16, viewWidth), h3 = std::max(16, height - n);
  const auto now = std::chrono::steady_clock::now();
  const bool stale = version != s.view3dVersion || s.view3dDirty || s.camera3d.width != w3 || s.camera3d.height != h3;
  if (stale && (!s.session->running() || now - s.view3dAt > std::chrono::seconds(1))) {
    s.camera3d = s.orbit.camera(render::gridBounds(s.session->source()), w3, h3);
    if (s.volumeRendering) {
      if (!s.volumeTarget || s.volumeTarget->width() != w3 || s.volumeTarget->height() != h3)
        s.volumeTarget = std::make_unique<gl::Framebuffer>(w3, h3);
      s.volumeTarget->bind();
      if (!s.pagedPhi || s.pagedPhiVersion != s.session->phiVersion()) {
        s.pagedPhi = std::make_unique<levelset::PagedPhiGpu>(s.session->levelSet());
        s.pagedPhiVersion = s.session->phiVersion();
      }
      s.volume->draw(*s.pagedPhi,
                     {.camera = s.camera3d, .window = s.window, .opacity = s.opacity, .scan = s.showScan, .insideOnly = s.insideOnly,
                      .clip = s.clip()});
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
    } else {
      s.surface.set(surfacePicture(w3, h3));
    }
    s.view3dVersion = version, s.view3dDirty = false, s.view3dAt = now;
  }
  if (s.volumeRendering && s.volumeTarget)
    glBlitNamedFramebuffer(s.volumeTarget->id(), 0, 0, 0, w3, h3, 0, 0, w3, h3, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  else
    s.surface.blit(0, n, height);
}

// The world point under picture position (x, y) of the 3D view: the clipping plane's cut face, or

void Viewer::drawView(int width, int height) {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, width, height);
  glClearColor(1, 1, 1, 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const int viewWidth = std::max(16, width - kPanelWidth);
  if (mode_ == Mode::Segment && segment_) return drawSegment(width, height);
  if (!target_ || target_->width() != viewWidth || target_->height() != height)
    target_ = std::make_unique<gl::Framebuffer>(viewWidth, height);
  if (mode_ == Mode::Mesh && model_) {
    ModelView& m = *model_;
    const render::Camera camera = m.orbit.camera(m.scene->bounds(), viewWidth, height);
    const render::CpuRefinement cpu = m.viewDependent ? render::CpuRefinement{.mode = render::CpuRefinement::Mode::Pixels}
                                              : render::CpuRefinement{.mode = render::CpuRefinement::Mode::Level, .level = m.cpuLevel};
    const render::GpuRefinement gpu = m.viewDependent ? render::GpuRefinement{.mode = render::GpuRefinement::Mode::Pixels}
                                              : render::GpuRefinement{.mode = render::GpuRefinement::Mode::Level, .halvings = m.gpuHalvings};
    render::drawFrame(*m.scene, atlasRenderer(), cpu, gpu, camera, {.wireframe = m.wire, .colourByChart = m.chartColours}, *target_);
    m.camera = camera, m.gpu = gpu;
  } else if (mode_ == Mode::Tree && tree_) {
    TreeView& t = *tree_;
    target_->bind();
    t.camera = t.orbit.camera(t.box, viewWidth, height);
    const dvt::GpuTreeBuffers buffers = t.painting ? t.painting->buffers() : dvt::GpuTreeBuffers{t.pointers->id(), t.cells->id()};
    dvtRenderer().draw(buffers, t.painting ? t.painting->nodeCount() : t.tree.nodeCount(), t.tree.frame,
                       {.camera = t.camera, .mode = t.cubes ? render::DvtRenderMode::Cubes : render::DvtRenderMode::RayCast});
  } else {
    return;
  }
  glBlitNamedFramebuffer(target_->id(), 0, 0, 0, viewWidth, height, 0, 0, viewWidth, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (treeDabAt_ && mode_ == Mode::Tree) {  // the dab's latency: its picture is in the window's back buffer
    glFinish();
    treeDabMs_.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - *treeDabAt_).count());
    treeDabAt_.reset();
  }
}

}  // namespace isoatlas::viewer::window
