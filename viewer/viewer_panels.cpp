// The window's controls on the right (Dear ImGui): one panel per view, the menu and the status line.
#include "viewer/viewer_state.h"

#include <imgui.h>

#include <algorithm>
#include <cstdint>

namespace isoatlas::viewer::window {

void Viewer::segmentPanel() {
  SegmentView& s = *segment_;
  SegmentationSession& session = *s.session;
  ImGui::TextUnformatted(s.file.c_str());
  const bool running = session.running();
  if (ImGui::Button(running ? "pause" : "run")) running ? session.pause() : session.start();
  ImGui::SameLine();
  if (ImGui::Button("step")) session.requestSteps(1);
  ImGui::SameLine();
  if (ImGui::Button("undo") && session.canUndo()) session.undo();
  ImGui::SameLine();
  if (ImGui::Button("redo") && session.canRedo()) session.redo();
  ImGui::Text("%d steps, %.1f steps/s (%s)", session.iterations(), running ? session.stepsPerSecond() : 0.0,
              session.levelSet().backendName().c_str());
  ImGui::Text("%lld active pages", (long long)session.activePages());
  levelset::SpeedParams p = session.params();
  const float lo = float(s.range.min), hi = float(s.range.max);
  bool changed = ImGui::SliderFloat("T", &p.target, lo, hi);
  changed |= ImGui::SliderFloat("eps", &p.width, std::max(1e-3f, (hi - lo) * 1e-3f), std::max(1e-3f, (hi - lo) / 2));
  changed |= ImGui::SliderFloat("alpha", &p.alpha, 0, 1);
  if (changed) attempt([&] { session.setParams(p); });
  bool keep = session.topology() == levelset::Topology::Preserve;
  if (ImGui::Checkbox("keep the seeds' topology", &keep))
    attempt([&] { session.setTopology(keep ? levelset::Topology::Preserve : levelset::Topology::Free); });
  if (keep) {
    ImGui::SameLine();
    if (ImGui::Button("fill threads")) attempt([&] { session.fillThreads(); });
  }
  ImGui::Separator();
  ImGui::TextUnformatted("click on a slice to:");
  int tool = int(s.tool);
  ImGui::RadioButton("move the slices", &tool, int(Tool::Navigate));
  ImGui::SameLine();
  ImGui::RadioButton("probe", &tool, int(Tool::Probe));
  ImGui::RadioButton("seed in", &tool, int(Tool::SeedIn));
  ImGui::SameLine();
  ImGui::RadioButton("seed out", &tool, int(Tool::SeedOut));
  ImGui::SameLine();
  ImGui::RadioButton("brush", &tool, int(Tool::Brush));
  s.tool = Tool(tool);
  ImGui::SliderFloat("probe radius (mm)", &s.probeRadius, 1, 20);
  ImGui::SliderFloat("seed radius (mm)", &s.seedRadius, 1, 40);
  int shape = int(s.brushShape);
  ImGui::RadioButton("sphere", &shape, 0);
  ImGui::SameLine();
  ImGui::RadioButton("box", &shape, 1);
  ImGui::SameLine();
  ImGui::RadioButton("capsule", &shape, 2);
  s.brushShape = BrushShape(shape);
  ImGui::SliderFloat("brush size (mm)", &s.brushSize, 1, 60);
  ImGui::Checkbox("brush adds (else carves)", &s.brushUnion);
  ImGui::Checkbox("brush on the slice only (2D)", &s.brushInSlice);
  ImGui::SliderInt("brush depth (levels past the voxels)", &s.brushLevels, -6, 3);
  ImGui::Separator();
  // The intensity window: the slices' grey levels and the volume rendering's transfer function.
  float low = float(s.window.low), high = float(s.window.high);
  const bool lowMoved = ImGui::SliderFloat("window low", &low, float(s.range.min), float(s.range.max));
  const bool highMoved = ImGui::SliderFloat("window high", &high, float(s.range.min), float(s.range.max));
  const bool windowed = lowMoved || highMoved;
  if (windowed) s.window = {low, std::max(high, low + 1e-3f)};
  s.slicesDirty |= windowed;
  bool view3d = windowed;
  view3d |= ImGui::Checkbox("volume rendering (else the surface)", &s.volumeRendering);
  if (s.volumeRendering) {
    view3d |= ImGui::Checkbox("scan", &s.showScan);
    ImGui::SameLine();
    view3d |= ImGui::Checkbox("only inside", &s.insideOnly);
    view3d |= ImGui::SliderFloat("opacity", &s.opacity, 0.005f, 0.5f, "%.3f", ImGuiSliderFlags_Logarithmic);
    ImGui::TextUnformatted("clip through the slice point:");
    view3d |= ImGui::RadioButton("none", &s.clipAxis, -1);
    for (int a = 0; a < 3; ++a) ImGui::SameLine(), view3d |= ImGui::RadioButton(a == 0 ? "x" : a == 1 ? "y" : "z", &s.clipAxis, a);
    ImGui::SameLine();
    view3d |= ImGui::Checkbox("cut above", &s.clipAbove);
    ImGui::TextUnformatted("ctrl-click in 3D: the tool on the cut face or the surface (ctrl-drag paints with the brush)");
  }
  s.view3dDirty |= view3d;
  s.slicesDirty |= ImGui::Checkbox("contour", &s.contour);
  ImGui::SameLine();
  s.slicesDirty |= ImGui::Checkbox("speed", &s.speed);
  ImGui::SameLine();
  s.slicesDirty |= ImGui::Checkbox("crosshair", &s.crosshair);
  ImGui::InputText("file", pathField_, sizeof pathField_);
  if (ImGui::Button("save mask")) attempt([&] { saveMask(*pathField_ ? pathField_ : "mask.nii.gz"); });
  ImGui::SameLine();
  if (ImGui::Button("load mask")) attempt([&] { loadMask(*pathField_ ? pathField_ : "mask.nii.gz"); });
  ImGui::SameLine();
  if (job_) {
    const auto [task, fraction] = job_->progress();
    ImGui::ProgressBar(float(fraction), ImVec2(-1, 0), task.c_str());
  } else if (ImGui::Button("extract and build the model")) {
    attempt([&] { build(); });
  }
}

void Viewer::modelPanel() {
  ModelView& m = *model_;
  ImGui::TextUnformatted(m.name.c_str());
  ImGui::Checkbox("view-dependent (screen error)", &m.viewDependent);
  if (!m.viewDependent) {
    ImGui::SliderInt("CPU level", &m.cpuLevel, 0, 8);
    ImGui::SliderInt("GPU halvings", &m.gpuHalvings, 0, 4);
  }
  ImGui::Checkbox("wireframe", &m.wire);
  ImGui::SameLine();
  ImGui::Checkbox("chart colours", &m.chartColours);
  if (ImGui::Checkbox("grid of 5 x 5", &m.grid)) m.rebuild();
  ImGui::TextUnformatted("ctrl-click the model to stamp:");
  ImGui::InputText("word", m.stampWord, sizeof m.stampWord);
  ImGui::SliderFloat("stamp radius (mm)", &m.stampRadius, 1, 60);
  ImGui::SliderFloat("depth (mm)", &m.stampDepth, -5, 5);
  if (ImGui::Button("save model")) attempt([&] { saveModel(*pathField_ ? pathField_ : "model.isoatlas"); });
  if (ImGui::CollapsingHeader("atlas", ImGuiTreeNodeFlags_DefaultOpen) && !m.atlasPreview.empty()) {
    const float w = float(kPanelWidth - 20), h = w * float(m.atlasPreview.height()) / float(std::max(1, m.atlasPreview.width()));
    ImGui::Image(ImTextureID(std::intptr_t(m.atlasPreview.texture())), ImVec2(w, h));
  }
}

void Viewer::drawPanel(int width, int height, bool& screenshot, bool& quit) {
  ImGui::SetNextWindowPos(ImVec2(float(width - kPanelWidth), 0));
  ImGui::SetNextWindowSize(ImVec2(float(kPanelWidth), float(height)));
  ImGui::Begin("isoatlas", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_MenuBar);
  if (ImGui::BeginMenuBar()) {
    if (ImGui::BeginMenu("File")) {
      if (ImGui::MenuItem("Open the file named below") && *pathField_) attempt([&] { show(load(pathField_)); });
      if (ImGui::MenuItem("Screenshot", "P")) screenshot = true;
      if (ImGui::MenuItem("Quit")) quit = true;
      ImGui::EndMenu();
    }
    ImGui::EndMenuBar();
  }
  int mode = int(mode_);
  if (segment_) ImGui::RadioButton("segment", &mode, int(Mode::Segment)), ImGui::SameLine();
  if (model_) ImGui::RadioButton("mesh", &mode, int(Mode::Mesh)), ImGui::SameLine();
  if (tree_) ImGui::RadioButton("tree", &mode, int(Mode::Tree)), ImGui::SameLine();
  ImGui::NewLine();
  mode_ = Mode(mode);
  ImGui::Separator();
  if (mode_ == Mode::Segment && segment_) segmentPanel();
  if (mode_ == Mode::Mesh && model_) modelPanel();
  if (mode_ == Mode::Tree && tree_) {
    ImGui::TextUnformatted(tree_->name.c_str());
    ImGui::Text("%zu nodes, %zu leaves, depth %u", tree_->tree.nodeCount(), tree_->tree.leafCount(), tree_->tree.maxDepth());
    ImGui::Checkbox("cubes (else ray cast)", &tree_->cubes);
    ImGui::TextUnformatted("ctrl-drag on the view paints");
    const Vec3& h = tree_->tree.frame.spacing;
    const float voxel = float(std::min({h.x, h.y, h.z}));
    ImGui::SliderFloat("brush radius", &tree_->brushRadius, voxel, 64 * voxel);
    ImGui::Checkbox("brush adds (else carves)", &tree_->brushUnion);
    if (!treeDabMs_.empty()) ImGui::Text("last dab: %.1f ms to its picture", treeDabMs_.back());
    if (ImGui::Button("save tree")) attempt([&] { saveTree(*pathField_ ? pathField_ : "tree.dvt"); });
  }
  if (!segment_ && !model_ && !tree_) ImGui::TextUnformatted("File > Open: a volume, a model or a tree");
  ImGui::Separator();
  ImGui::Text("%.1f ms a frame", 1000.0 / std::max(1.0f, ImGui::GetIO().Framerate));
  if (ImGui::Button("screenshot (P)")) screenshot = true;
  ImGui::TextWrapped("%s", status_.c_str());
  ImGui::End();
}

}  // namespace isoatlas::viewer::window
