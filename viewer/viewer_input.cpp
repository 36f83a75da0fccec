// The mouse and the keys on the window's views: the segmentation's tools on the slices and, with
// ctrl, on the 3D view (picked through the volume rendering), the brush's strokes, stamping the
// model, painting the tree (ctrl-drag), orbiting; undo and redo.
#include "viewer/viewer_state.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE  // epoxy declares GL
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>

#include "render/ray_pick.h"

namespace isoatlas::viewer::window {

std::unique_ptr<dvt::DistanceSolid> Viewer::brushSolid(const Vec3& c) const {
  const double s = segment_->brushSize;
  switch (segment_->brushShape) {
    case BrushShape::Sphere: return dvt::sphereBrush(c, s);
    case BrushShape::Box: return dvt::boxBrush(c - Vec3{s, s, s}, c + Vec3{s, s, s});
    case BrushShape::Capsule: return dvt::capsuleBrush(c - Vec3{0, 0, s}, c + Vec3{0, 0, s}, s / 2);  // upright, as long as it is wide
  }
  throw Error("unknown brush shape");
}

std::optional<Vec3> Viewer::pick3d(double x, double y) const {
  const SegmentView& s = *segment_;
  const render::Camera& c = s.camera3d;
  const Vec3 d = c.rayThrough(x, y);
  const Volume& v = s.session->source();
  auto insideVolume = [&](const Vec3& ijk) {
    for (int a = 0; a < 3; ++a)
      if (ijk[a] < -0.5 || ijk[a] > double(v.dims[a]) - 0.5) return false;
    return true;
  };
  const std::optional<render::ClipPlane> clip = s.clip();
  double tStart = 0;
  if (clip) {
    const double rate = dot(clip->normal, d), side = dot(clip->normal, c.eye - clip->point);
    if (rate != 0) {
      const double t = -side / rate;
      const Vec3 p = c.eye + d * t;
      if (t > 0 && rate < 0 && insideVolume(v.worldToIndex(p))) return p;  // entering the kept side: the face
      if (rate < 0) tStart = std::max(tStart, t);
    }
  }
  const render::VoxelField phi = s.session->phi();
  const double step = 0.5 * std::min({v.spacing.x, v.spacing.y, v.spacing.z});
  const double far = norm(c.eye - render::volumeCentre(v)) + render::gridBounds(v).diagonal();
  for (double t = tStart; t < far; t += step) {
    const Vec3 p = c.eye + d * t;
    if (clip && dot(clip->normal, p - clip->point) > 0) continue;
    const Vec3 ijk = v.worldToIndex(p);
    if (!insideVolume(ijk)) continue;
    const auto i = std::clamp<std::int64_t>(std::lround(ijk.x), 0, v.dims[0] - 1), j = std::clamp<std::int64_t>(std::lround(ijk.y), 0, v.dims[1] - 1),
               k = std::clamp<std::int64_t>(std::lround(ijk.z), 0, v.dims[2] - 1);
    if (phi(i, j, k) > 0) return p;
  }
  return std::nullopt;
}

void Viewer::applyTool(const Vec3& at) {
  SegmentView& s = *segment_;
  switch (s.tool) {
    case Tool::Navigate: slice(at); break;
    case Tool::Probe: probe(at, s.probeRadius); break;
    case Tool::SeedIn: seed(at, s.seedRadius, true); break;
    case Tool::SeedOut: seed(at, s.seedRadius, false); break;
    case Tool::Brush:
      beginStroke(s.brushUnion, s.brushLevels);
      if (s.brushInSlice && s.strokeView < 3) s.stroke->keepToSlice(sliceNormalAxis(s.strokeView), at);
      try {
        brushAt(at);
      } catch (...) {
        s.stroke.reset();  // no empty stroke to commit on release
        throw;
      }
      break;
  }
}

// The brush's next dab at `at`: a sphere sweeps from its last dab; other shapes are stamped.
void Viewer::brushAt(const Vec3& at) {
  SegmentView& s = *segment_;
  if (s.brushShape == BrushShape::Sphere) strokeTo(at, s.brushSize);
  else strokeWith(*s.stroke->kept(brushSolid(at)));
  s.lastDab = at;
}

void Viewer::handleMouse(GLFWwindow* window, int width, int height) {
  double x = 0, y = 0;
  glfwGetCursorPos(window, &x, &y);
  int windowWidth = 1, windowHeight = 1;
  glfwGetWindowSize(window, &windowWidth, &windowHeight);
  x *= double(width) / std::max(1, windowWidth), y *= double(height) / std::max(1, windowHeight);  // to framebuffer pixels
  const ImGuiIO& io = ImGui::GetIO();
  const bool down = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  const bool rightDown = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  const bool pressed = down && !leftWasDown_;
  const double dx = x - lastX_, dy = y - lastY_;
  leftWasDown_ = down, lastX_ = x, lastY_ = y;
  if (!down && segment_ && segment_->stroke) attempt([&] { endStroke(); });  // released anywhere
  if (!down && tree_ && tree_->stroking && tree_->scriptedRadius == 0) attempt([&] { endTreeStroke(); });
  if (io.WantCaptureMouse || x >= width - kPanelWidth) return;
  render::Orbit* orbit = mode_ == Mode::Mesh && model_ ? &model_->orbit : mode_ == Mode::Tree && tree_ ? &tree_->orbit : nullptr;
  int viewHeight = height;
  if (mode_ == Mode::Segment && segment_) {
    SegmentView& s = *segment_;
    const int n = s.panelSize;
    if (y >= n || x >= 3 * n) {  // the 3D view
      if (pressed && io.KeyCtrl && s.volumeRendering) {
        s.strokeView = 3;
        if (const auto at = pick3d(x, y - n)) attempt([&] { applyTool(*at); });
        else status_ = "nothing there to pick";
        return;
      }
      if (down && s.stroke && s.strokeView == 3) {  // a stroke begun with ctrl-click goes on where the mouse picks
        if (const auto at = pick3d(x, y - n); at && norm(*at - s.lastDab) >= 0.25 * s.brushSize) attempt([&] { brushAt(*at); });
        return;
      }
      orbit = &s.orbit;
      viewHeight = height - n;
      if (((down || rightDown) && (dx != 0 || dy != 0)) || io.MouseWheel != 0) s.view3dDirty = true;
    } else {
      const int panel = int(x) / n;
      const render::SliceLayout layout(s.session->source(), s.point, n);
      const Vec3 at = layout.world(panel, x - panel * n, y);
      if (io.MouseWheel != 0) {  // scroll through the slices: one voxel along the panel's normal
        const int axis = sliceNormalAxis(panel);
        const double step = std::min({s.session->source().spacing.x, s.session->source().spacing.y, s.session->source().spacing.z});
        s.point[axis] += io.MouseWheel > 0 ? step : -step;
        s.slicesDirty = s.view3dDirty = true;
      }
      if (pressed || (down && s.tool == Tool::Navigate)) {
        s.strokeView = panel;
        attempt([&] { applyTool(at); });
      } else if (down && s.stroke && s.strokeView == panel && norm(at - s.lastDab) >= 0.25 * s.brushSize) {  // dragging the brush
        attempt([&] { brushAt(at); });
      }
      return;
    }
  }
  if (mode_ == Mode::Tree && tree_ && down && (io.KeyCtrl || tree_->stroking) && tree_->scriptedRadius == 0) {
    // Ctrl-drag paints the tree where the mouse picks it (on the tree as it was when the stroke began).
    TreeView& t = *tree_;
    const std::optional<Vec3> at = pickTree(t.tree, t.camera.eye, t.camera.rayThrough(x, y));
    if (!at) {
      if (pressed) status_ = "nothing there to paint";
    } else if (pressed || norm(*at - t.lastDab) >= 0.25 * t.brushRadius) {
      attempt([&] { treeDab(*at, t.brushRadius, t.brushUnion); });
    }
    return;
  }
  if (mode_ == Mode::Mesh && model_ && pressed && io.KeyCtrl) {
    ModelView& m = *model_;
    const Mesh drawn = atlasRenderer().capture(m.scene->items(), m.camera, m.scene->bounds(), m.gpu);
    if (const auto at = render::rayPick(drawn, m.camera.eye, m.camera.rayThrough(x, y)))
      attempt([&] { stamp(*at, m.stampWord, m.stampRadius, m.stampDepth); });
    else
      status_ = "nothing there to stamp";
    return;
  }
  if (!orbit) return;
  if (down) orbit->drag(dx, dy);
  if (rightDown) orbit->pan(dx, dy, viewHeight);
  if (io.MouseWheel != 0) orbit->zoom(io.MouseWheel);
}

void Viewer::handleKeys(GLFWwindow* window) {
  const bool zDown = glfwGetKey(window, GLFW_KEY_Z) == GLFW_PRESS, yDown = glfwGetKey(window, GLFW_KEY_Y) == GLFW_PRESS;
  const bool zPressed = zDown && !zWasDown_, yPressed = yDown && !yWasDown_;
  zWasDown_ = zDown, yWasDown_ = yDown;
  const ImGuiIO& io = ImGui::GetIO();
  if (!segment_ || segment_->stroke || io.WantCaptureKeyboard || !io.KeyCtrl) return;  // not while painting
  if ((zPressed && !io.KeyShift) && segment_->session->canUndo()) attempt([&] { undo(); });
  else if ((yPressed || (zPressed && io.KeyShift)) && segment_->session->canRedo()) attempt([&] { redo(); });
}


}  // namespace isoatlas::viewer::window
