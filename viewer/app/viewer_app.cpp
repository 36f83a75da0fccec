#include "viewer/app/viewer_app.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE  // epoxy declares GL
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <optional>

#include "atlas/atlas_previews.h"
#include "atlas/model_file.h"
#include "atlas/stamp_detail.h"
#include "core/error.h"
#include "core/gl/context.h"
#include "core/gl/resources.h"
#include "core/gz_file.h"
#include "core/image.h"
#include "core/text.h"
#include "core/volume_io.h"
#include "extract/extract_surface.h"
#include "levelset/dvt/dvt_file.h"
#include "viewer/app/brush_edit.h"
#include "viewer/app/image_panel.h"
#include "viewer/orbit.h"
#include "viewer/app/segmentation_session.h"
#include "viewer/app/view_script.h"
#include "viewer/dvt_render.h"
#include "viewer/mesh_render.h"
#include "viewer/ray_pick.h"
#include "viewer/scene.h"
#include "viewer/slice_render.h"
#include "viewer/volume_render.h"

namespace isoatlas::viewer {
namespace {

namespace dvt = levelset::dvt;

constexpr int kPanelWidth = kControlsWidth;

enum class Mode { Segment, Mesh, Tree };
const char* modeName(Mode m) { return m == Mode::Segment ? "segment" : m == Mode::Mesh ? "mesh" : "tree"; }
enum class Tool { Navigate, Probe, SeedIn, SeedOut, Brush };
enum class BrushShape { Sphere, Box, Capsule };

// A file as read before any window opens, so that a bad one is one line.
struct Loaded {
  std::string file;
  std::optional<Volume> volume;
  std::optional<atlas::Model> model;
  std::optional<dvt::VolumeTree> tree;
};
Loaded load(const std::string& file) {
  Loaded l{.file = file};
  if (endsWith(file, ".isoatlas"))
    l.model = atlas::readModel(file);
  else if (endsWith(file, ".dvt"))
    l.tree = dvt::readDvt(file);
  else
    l.volume = readVolume(file);
  return l;
}

// The voxel axis a slice panel is normal to: k for the axial (0), j the coronal (1), i the sagittal (2).
int sliceNormalAxis(int panel) { return 2 - panel; }

struct SegmentView {
  std::unique_ptr<SegmentationSession> session;
  std::string file;
  IntensityWindow window;
  ValueRange range;
  Vec3 point;
  bool contour = true, speed = false, crosshair = true;
  Tool tool = Tool::Navigate;
  float probeRadius = 3, seedRadius = 6, brushSize = 8;
  BrushShape brushShape = BrushShape::Sphere;
  bool brushUnion = false;
  bool brushInSlice = false;  // a 2D brush: on a slice it paints that slice's layer of voxels only
  int brushLevels = 0;  // the brush's tree depth past the voxels' (negative: coarser cells)
  std::unique_ptr<BrushStroke> stroke;  // while the brush is dragged; the slices show its preview
  Vec3 lastDab;
  int strokeView = 0;  // where the stroke began: slice panel 0, 1, 2, or 3 the 3D view; it paints only there
  // The slices as last drawn, and what they showed.
  ImagePanel slices;
  bool slicesDirty = true;
  std::uint64_t slicesVersion = ~0ull;
  int panelSize = 0;
  // The 3D view below the slices: the volume rendering of the scan and the level set from its pages
  // (with a clipping plane through the slice point), or the surface extracted from the pages; drawn
  // again when the segmentation, the camera or the options change (at most once a second while the
  // solver runs).
  bool volumeRendering = true, insideOnly = false, showScan = true;
  float opacity = 0.08f;
  int clipAxis = -1;  // -1 none; 0, 1, 2: x, y, z
  bool clipAbove = false;  // cut away what lies above the slice point along the axis (else below)
  std::unique_ptr<VolumeRenderer> volume;
  std::unique_ptr<gl::Framebuffer> volumeTarget;
  // The level set's pages as the volume renderer reads them, made again only when phi changes (an
  // orbit or a new T or eps redraws from the same; on the CPU backend making them uploads the pool).
  std::unique_ptr<levelset::PagedPhiGpu> pagedPhi;
  std::uint64_t pagedPhiVersion = ~0ull;
  ImagePanel surface;
  std::uint64_t view3dVersion = ~0ull;
  bool view3dDirty = true;
  std::chrono::steady_clock::time_point view3dAt;
  Orbit orbit;
  Camera camera3d;  // the volume rendering's, for picking
  std::optional<ClipPlane> clip() const {
    if (clipAxis < 0) return std::nullopt;
    Vec3 n{0, 0, 0};
    n[clipAxis] = clipAbove ? 1 : -1;
    return ClipPlane{point, n};
  }
};

struct ModelView {
  std::string name;
  atlas::Model model;
  std::unique_ptr<Scene> scene;
  int cpuLevel = 2, gpuHalvings = 1;
  bool viewDependent = false, wire = false, chartColours = false, grid = false;
  ImagePanel atlasPreview;
  Orbit orbit;
  // The last frame's camera and GPU refinement, for picking what it drew.
  Camera camera;
  GpuRefinement gpu;
  // The stamp tool: a word pressed into the surface where the mouse picks it.
  char stampWord[64] = "isoatlas";
  float stampRadius = 10, stampDepth = 0.8f;
  // The scene again (after the grid switch, or a stamp changed the atlas the scene uploaded).
  void rebuild() {
    scene = std::make_unique<Scene>(std::vector<const atlas::Model*>{&model});
    if (grid) scene->grid(5);
    atlasPreview.set(atlas::positionPreview(model.atlas));
  }
};

struct TreeView {
  std::string name;
  dvt::VolumeTree tree;
  std::unique_ptr<gl::Buffer> pointers, cells;
  Box box;
  bool cubes = false;
  Orbit orbit;
};

void requireDisplay() {
  const char* x = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  if ((!x || !*x) && (!wayland || !*wayland))
    throw Error("isoatlas view needs a display (DISPLAY is not set): run it on a desktop, or under xvfb-run; "
                "`isoatlas render` and `isoatlas edit --render` make the same pictures headless");
}

levelset::Backend chooseSolver(const std::string& choice, const gl::Context& context) {
  return levelset::backendFor(choice, context.info().software());
}

std::string formatPoint(const Vec3& p) {
  char text[96];
  std::snprintf(text, sizeof text, "%.1f,%.1f,%.1f", p.x, p.y, p.z);
  return text;
}

// The window's state and every action on it; the mouse, the panels and the script all go through these.
class Viewer {
public:
  Viewer(gl::Context& context, const ViewerOptions& options)
      : context_(context), options_(options), backend_(chooseSolver(options.backend, context)) {}

  // ---- actions (throw Error on bad input; the panels show it, the script stops with it) ----
  void show(Loaded loaded) {
    if (loaded.volume) {
      segment_.emplace();
      segment_->file = loaded.file;
      segment_->range = valueRange(*loaded.volume);
      segment_->point = volumeCentre(*loaded.volume);
      segment_->session = std::make_unique<SegmentationSession>(std::move(*loaded.volume), backend_);
      segment_->window = segment_->session->window();
      segment_->volume = std::make_unique<VolumeRenderer>();
      segment_->volume->setSource(segment_->session->source());
      segment_->volumeRendering = !context_.info().software();  // llvmpipe takes seconds a picture
      mode_ = Mode::Segment;
    } else if (loaded.model) {
      showModel(std::move(*loaded.model), loaded.file);
    } else if (loaded.tree) {
      showTree(std::move(*loaded.tree), loaded.file);
    }
  }
  void setMode(const std::string& name) {
    const Mode m = name == "segment" ? Mode::Segment : name == "mesh" ? Mode::Mesh : Mode::Tree;
    require(m != Mode::Segment || segment_, "mode segment: open a volume first");
    require(m != Mode::Mesh || model_, "mode mesh: open a model (.isoatlas) or build one from the segmentation first");
    require(m != Mode::Tree || tree_, "mode tree: open a tree (.dvt) or brush the segmentation first");
    mode_ = m;
  }
  void slice(const Vec3& p) {
    seg().point = p;
    seg().slicesDirty = seg().view3dDirty = true;
  }
  void probe(const Vec3& p, double radius) {
    const auto r = seg().session->probe(p, radius);
    status_ = "probe at " + formatPoint(p) + ": T " + std::to_string(r.mean) + ", eps " + std::to_string(r.std);
  }
  void seed(const Vec3& p, double radius, bool add) {
    seg().session->seed(p, radius, add);
    status_ = std::string(add ? "seed" : "unseed") + " at " + formatPoint(p);
  }
  void set(const std::string& parameter, double value) {
    levelset::SpeedParams p = seg().session->params();
    (parameter == "t" ? p.target : parameter == "eps" ? p.width : p.alpha) = float(value);
    seg().session->setParams(p);
  }
  void run(int steps) { seg().session->requestSteps(steps); }
  void undo() {
    require(seg().session->canUndo(), "undo: nothing to undo");
    seg().session->undo();
  }
  void redo() {
    require(seg().session->canRedo(), "redo: nothing to redo");
    seg().session->redo();
  }
  // A brush stroke: begun with the tree of the segmentation, dabs as the mouse moves (or as a script
  // lists them), ended with its mask as the segmentation (one undo takes the whole stroke back).
  void beginStroke(bool add, int levels) {
    seg().session->pause();  // the stroke's mask replaces the segmentation as it was when the stroke began
    seg().stroke = std::make_unique<BrushStroke>(seg().session->levelSet(), add ? dvt::Op::Union : dvt::Op::Subtract,
                                                 backend_, levels);
  }
  void strokeWith(const dvt::Solid& shape) {
    seg().stroke->apply(shape);
    seg().slicesDirty = true;
  }
  void strokeTo(const Vec3& at, double radius) {
    seg().stroke->dabTo(at, radius);
    seg().slicesDirty = true;
  }
  void endStroke() {
    SegmentView& s = seg();
    const std::unique_ptr<BrushStroke> stroke = std::move(s.stroke);
    const std::size_t dabs = stroke->dabs();
    BrushResult r = stroke->finish();
    s.session->replaceMask(r.mask);
    showTree(r.tree->tree(), "brushed segmentation");
    mode_ = Mode::Segment;
    s.slicesDirty = true;
    status_ = "brush stroke of " + std::to_string(dabs) + (dabs == 1 ? " dab: " : " dabs: ") + std::to_string(tree_->tree.nodeCount()) + " nodes";
  }
  void brush(const std::string& shape, bool add, int levels = 0) {
    const auto solid = dvt::parseBrush(shape);
    beginStroke(add, levels);
    strokeWith(*solid);
    endStroke();
    status_ = std::string(add ? "union " : "subtract ") + shape + ": " + std::to_string(tree_->tree.nodeCount()) + " nodes";
  }
  // A sphere brush of `radius` mm dragged through `points`; with `sliceAxis` (0 i, 1 j, 2 k) only in
  // the slice of voxels normal to that axis through the first point.
  void stroke(const std::vector<Vec3>& points, double radius, bool add, int sliceAxis = -1) {
    beginStroke(add, 0);
    if (sliceAxis >= 0) seg().stroke->keepToSlice(sliceAxis, points.front());
    for (const Vec3& p : points) strokeTo(p, radius);
    endStroke();
  }
  void build() {
    require(bool(options_.buildModel), "build: this window was opened without the model builder");
    require(!job_, "build: a model is being built already");
    SegmentationSession& s = *seg().session;
    require(s.activePages() > 0, "build: the segmentation is empty (seed it first)");
    Mesh surface = extract::extractLevelSet(s.levelSet(), {.largestComponent = true, .backend = backend_});
    require(surface.faceCount() > 0, "build: the segmentation has no surface");
    job_ = std::make_unique<ModelJob>(std::move(surface), options_.buildModel);
    status_ = "building the model";
  }
  void view3d(bool volume) {
    seg().volumeRendering = volume;
    seg().view3dDirty = true;
  }
  // "off", or the axis and the side cut away: "+x" cuts what lies at larger x than the slice point.
  void clip(const std::string& how) {
    SegmentView& s = seg();
    s.clipAxis = how == "off" ? -1 : how[1] - 'x';
    s.clipAbove = how[0] == '+';
    s.view3dDirty = true;
  }
  void levels(int cpu, int gpu) {
    mod().cpuLevel = cpu, mod().gpuHalvings = gpu;
    mod().viewDependent = false;
  }
  void wireframe(bool on) { mod().wire = on; }
  // A word pressed `depth` mm into the model's surface nearest `at`, fitting a disc of `radius` mm.
  void stamp(const Vec3& at, const std::string& word, double radius, double depth) {
    ModelView& m = mod();
    const atlas::StampStats st =
        atlas::stampDetail(m.model.base, m.model.atlas, {.image = renderText(word, 128), .at = at, .radius = radius, .depth = depth});
    require(st.texelsChanged + st.detailTexelsChanged > 0, "stamp: the word reaches no part of the surface there");
    m.rebuild();
    status_ = "stamped \"" + word + "\" on " + std::to_string(st.detailTiles) + " tiles";
  }
  void treeRender(bool cubes) {
    require(bool(tree_), "render: no tree is open");
    tree_->cubes = cubes;
  }
  void saveMask(const std::string& path) {
    seg().session->saveMask(path);
    status_ = "saved " + path;
  }
  void saveModel(const std::string& path) {
    atlas::writeModel(path, mod().model);
    status_ = "saved " + path;
  }

  // ---- the frame ----
  // Takes the finished build, steps the solver within the frame's budget.
  void update() {
    if (job_ && job_->done()) {
      std::unique_ptr<ModelJob> job = std::move(job_);
      try {
        showModel(job->take(), "built from " + seg().file);
        status_ = "model built in " + std::to_string(int(job->seconds())) + " s";
      } catch (const std::exception& e) {
        buildError_ = e.what();
        status_ = std::string("build failed: ") + e.what();
      }
    }
    if (segment_) segment_->session->advance(25);
  }
  bool busy() const { return (segment_ && segment_->session->running()) || job_; }
  // An error the last build left for the script, once.
  std::string takeBuildError() { return std::exchange(buildError_, {}); }
  Mode mode() const { return mode_; }

  void drawPanel(int width, int height, bool& screenshot, bool& quit);
  void drawView(int width, int height);
  void handleMouse(GLFWwindow* window, int width, int height);
  // Ctrl+Z undoes the last edit of the segmentation, Ctrl+Y (or Ctrl+Shift+Z) redoes it.
  void handleKeys(GLFWwindow* window);
  int iterations() const { return segment_ ? segment_->session->iterations() : 0; }
  std::string backendName() const { return segment_ ? segment_->session->levelSet().backendName() : ""; }

private:
  SegmentView& seg() {
    require(bool(segment_), "no volume is open (open one to segment it)");
    return *segment_;
  }
  ModelView& mod() {
    require(bool(model_), "no model is open (open a .isoatlas or build one)");
    return *model_;
  }
  void showModel(atlas::Model model, const std::string& name) {
    model_.reset();
    model_.emplace();
    model_->name = name;
    model_->model = std::move(model);
    model_->rebuild();
    mode_ = Mode::Mesh;
  }
  void showTree(dvt::VolumeTree tree, const std::string& name) {
    tree_.emplace();
    tree_->name = name;
    tree_->tree = std::move(tree);
    tree_->box = insideBounds(tree_->tree);
    tree_->pointers = std::make_unique<gl::Buffer>(gl::Buffer::of(tree_->tree.pointers));
    tree_->cells = std::make_unique<gl::Buffer>(gl::Buffer::of(tree_->tree.cells));
    mode_ = Mode::Tree;
  }
  // UI calls: an error becomes the status line.
  template <class F>
  void attempt(F&& f) {
    try {
      f();
    } catch (const std::exception& e) {
      status_ = e.what();
    }
  }
  std::unique_ptr<dvt::DistanceSolid> brushSolid(const Vec3& at) const;
  void segmentPanel();
  void modelPanel();
  void drawSegment(int width, int height);
  Image surfacePicture(int width, int height);
  std::optional<Vec3> pick3d(double x, double y) const;
  void applyTool(const Vec3& at);
  void brushAt(const Vec3& at);

  gl::Context& context_;
  const ViewerOptions& options_;
  levelset::Backend backend_;
  // Compiled when a tree or a model is first drawn, not when the window opens.
  std::optional<DvtRenderer> dvtRenderer_;
  std::optional<AtlasRenderer> atlasRenderer_;
  DvtRenderer& dvtRenderer() { return dvtRenderer_ ? *dvtRenderer_ : dvtRenderer_.emplace(); }
  AtlasRenderer& atlasRenderer() { return atlasRenderer_ ? *atlasRenderer_ : atlasRenderer_.emplace(); }
  std::optional<SegmentView> segment_;
  std::optional<ModelView> model_;
  std::optional<TreeView> tree_;
  std::unique_ptr<ModelJob> job_;
  std::unique_ptr<gl::Framebuffer> target_;
  Mode mode_ = Mode::Segment;
  std::string status_, buildError_;
  char pathField_[256] = "";
  bool leftWasDown_ = false, zWasDown_ = false, yWasDown_ = false;
  double lastX_ = 0, lastY_ = 0;
};

std::unique_ptr<dvt::DistanceSolid> Viewer::brushSolid(const Vec3& c) const {
  const double s = segment_->brushSize;
  switch (segment_->brushShape) {
    case BrushShape::Sphere: return dvt::sphereBrush(c, s);
    case BrushShape::Box: return dvt::boxBrush(c - Vec3{s, s, s}, c + Vec3{s, s, s});
    case BrushShape::Capsule: return dvt::capsuleBrush(c - Vec3{0, 0, s}, c + Vec3{0, 0, s}, s / 2);  // upright, as long as it is wide
  }
  throw Error("unknown brush shape");
}

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
  }
  if (!segment_ && !model_ && !tree_) ImGui::TextUnformatted("File > Open: a volume, a model or a tree");
  ImGui::Separator();
  ImGui::Text("%.1f ms a frame", 1000.0 / std::max(1.0f, ImGui::GetIO().Framerate));
  if (ImGui::Button("screenshot (P)")) screenshot = true;
  ImGui::TextWrapped("%s", status_.c_str());
  ImGui::End();
}

Image Viewer::surfacePicture(int width, int height) {
  SegmentationSession& session = *segment_->session;
  MeshRenderOptions o{.width = width, .height = height, .viewDirection = segment_->orbit.direction() * -1.0};
  if (session.activePages() == 0) {  // nothing segmented yet: the background
    Image blank(width, height, 3);
    std::fill(blank.pixels.begin(), blank.pixels.end(), std::uint8_t(255));
    return blank;
  }
  const Mesh surface = extract::extractLevelSet(session.levelSet(), {.backend = backend_});
  return renderMesh(surface, o);
}

void Viewer::drawSegment(int width, int height) {
  SegmentView& s = *segment_;
  const int viewWidth = width - kPanelWidth;
  const int n = slicePanelSize(width, height);
  const std::uint64_t version = s.session->version();
  if (s.slicesDirty || version != s.slicesVersion || n != s.panelSize) {
    SliceOptions o{.panelSize = n, .window = s.window, .crosshair = s.crosshair};
    if (s.stroke) o.mask = &s.stroke->preview();  // the stroke so far, tinted over the segmentation's contour
    if (s.contour) o.phi = s.session->phi();
    const levelset::SpeedParams params = s.session->params();
    if (s.speed) o.speed = &params;
    s.slices.set(renderSlices(s.session->source(), s.point, o));
    s.slicesDirty = false, s.slicesVersion = version, s.panelSize = n;
  }
  s.slices.blit(0, 0, height);
  // The 3D view below the slices.
  const int w3 = std::max(16, viewWidth), h3 = std::max(16, height - n);
  const auto now = std::chrono::steady_clock::now();
  const bool stale = version != s.view3dVersion || s.view3dDirty || s.camera3d.width != w3 || s.camera3d.height != h3;
  if (stale && (!s.session->running() || now - s.view3dAt > std::chrono::seconds(1))) {
    s.camera3d = s.orbit.camera(gridBounds(s.session->source()), w3, h3);
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
// the first voxel inside the level set along the ray (phi read from the pages on the host).
std::optional<Vec3> Viewer::pick3d(double x, double y) const {
  const SegmentView& s = *segment_;
  const Camera& c = s.camera3d;
  const Vec3 d = c.rayThrough(x, y);
  const Volume& v = s.session->source();
  auto insideVolume = [&](const Vec3& ijk) {
    for (int a = 0; a < 3; ++a)
      if (ijk[a] < -0.5 || ijk[a] > double(v.dims[a]) - 0.5) return false;
    return true;
  };
  const std::optional<ClipPlane> clip = s.clip();
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
  const VoxelField phi = s.session->phi();
  const double step = 0.5 * std::min({v.spacing.x, v.spacing.y, v.spacing.z});
  const double far = norm(c.eye - volumeCentre(v)) + gridBounds(v).diagonal();
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
    const Camera camera = m.orbit.camera(m.scene->bounds(), viewWidth, height);
    const CpuRefinement cpu = m.viewDependent ? CpuRefinement{.mode = CpuRefinement::Mode::Pixels}
                                              : CpuRefinement{.mode = CpuRefinement::Mode::Level, .level = m.cpuLevel};
    const GpuRefinement gpu = m.viewDependent ? GpuRefinement{.mode = GpuRefinement::Mode::Pixels}
                                              : GpuRefinement{.mode = GpuRefinement::Mode::Level, .halvings = m.gpuHalvings};
    drawFrame(*m.scene, atlasRenderer(), cpu, gpu, camera, {.wireframe = m.wire, .colourByChart = m.chartColours}, *target_);
    m.camera = camera, m.gpu = gpu;
  } else if (mode_ == Mode::Tree && tree_) {
    TreeView& t = *tree_;
    target_->bind();
    dvtRenderer().draw({t.pointers->id(), t.cells->id()}, t.tree.nodeCount(), t.tree.frame,
                      {.camera = t.orbit.camera(t.box, viewWidth, height), .mode = t.cubes ? DvtRenderMode::Cubes : DvtRenderMode::RayCast});
  } else {
    return;
  }
  glBlitNamedFramebuffer(target_->id(), 0, 0, 0, viewWidth, height, 0, 0, viewWidth, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
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
  if (io.WantCaptureMouse || x >= width - kPanelWidth) return;
  Orbit* orbit = mode_ == Mode::Mesh && model_ ? &model_->orbit : mode_ == Mode::Tree && tree_ ? &tree_->orbit : nullptr;
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
      const SliceLayout layout(s.session->source(), s.point, n);
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
  if (mode_ == Mode::Mesh && model_ && pressed && io.KeyCtrl) {
    ModelView& m = *model_;
    const Mesh drawn = atlasRenderer().capture(m.scene->items(), m.camera, m.scene->bounds(), m.gpu);
    if (const auto at = rayPick(drawn, m.camera.eye, m.camera.rayThrough(x, y)))
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

// A stroke action's points: its numbers after the radius, three a point.
std::vector<Vec3> strokePoints(const std::vector<double>& numbers) {
  std::vector<Vec3> points;
  for (std::size_t i = 1; i + 2 < numbers.size(); i += 3) points.push_back({numbers[i], numbers[i + 1], numbers[i + 2]});
  return points;
}

// Replays a script's actions one per frame, waiting where an action takes time.
class ScriptPlayer {
public:
  explicit ScriptPlayer(std::vector<ViewAction> actions) : actions_(std::move(actions)) {}
  bool finished() const { return next_ >= actions_.size(); }
  // The next action, unless the viewer is still busy with the last; screenshots and quit are left
  // to the end of the frame.
  void step(Viewer& viewer, std::string& screenshot, bool& quit) {
    if (const std::string error = viewer.takeBuildError(); !error.empty())
      throw Error((next_ > 0 ? actions_[next_ - 1].where() + ": " : std::string()) + "build: " + error);
    if (framesLeft_ > 0) {
      --framesLeft_;
      return;
    }
    if (finished() || viewer.busy()) return;
    const ViewAction& a = actions_[next_++];
    try {
      perform(a, viewer, screenshot, quit);
    } catch (const std::exception& e) {
      throw Error(a.where() + ": " + e.what());
    }
  }

private:
  void perform(const ViewAction& a, Viewer& v, std::string& screenshot, bool& quit) {
    const auto& n = a.numbers;
    const std::string& verb = a.verb;
    if (verb == "open") v.show(load(a.word));
    else if (verb == "mode") v.setMode(a.word);
    else if (verb == "slice") v.slice({n[0], n[1], n[2]});
    else if (verb == "probe") v.probe({n[0], n[1], n[2]}, n[3]);
    else if (verb == "seed" || verb == "unseed") v.seed({n[0], n[1], n[2]}, n[3], verb == "seed");
    else if (verb == "set") v.set(a.word, n[0]);
    else if (verb == "run") v.run(int(n[0]));
    else if (verb == "undo") v.undo();
    else if (verb == "redo") v.redo();
    else if (verb == "brush") v.brush(a.word, a.on);
    else if (verb == "stroke") v.stroke(strokePoints(n), n[0], a.on);
    else if (verb == "paint") v.stroke(strokePoints(n), n[0], a.on, int(a.word[0] - 'i'));
    else if (verb == "build") v.build();
    else if (verb == "levels") v.levels(int(n[0]), int(n[1]));
    else if (verb == "view3d") v.view3d(a.word == "volume");
    else if (verb == "stamp") v.stamp({n[0], n[1], n[2]}, a.word, n[3], n[4]);
    else if (verb == "clip") v.clip(a.word);
    else if (verb == "wireframe") v.wireframe(a.on);
    else if (verb == "render") v.treeRender(a.word == "cubes");
    else if (verb == "save-mask") v.saveMask(a.word);
    else if (verb == "save-model") v.saveModel(a.word);
    else if (verb == "screenshot") screenshot = a.word;
    else if (verb == "frames") framesLeft_ = int(n[0]);
    else if (verb == "quit") quit = true;
  }
  std::vector<ViewAction> actions_;
  std::size_t next_ = 0;
  int framesLeft_ = 0;
};

// Dear ImGui over the window, torn down however the loop ends.
struct ImGuiScope {
  explicit ImGuiScope(GLFWwindow* window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini beside the user's files
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 450");
  }
  ~ImGuiScope() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
};

}  // namespace

int slicePanelSize(int width, int height) { return std::max(16, std::min((width - kControlsWidth) / 3, height / 2)); }

ViewerReport runViewer(const ViewerOptions& options) {
  require(options.frames >= 0, "--frames must be >= 0");
  require(options.screenshot.empty() || endsWith(options.screenshot, ".png"), options.screenshot + ": --screenshot writes a PNG");
  // Read before any window opens, so a bad file or script is one line.
  std::vector<Loaded> files;
  for (const std::string& f : options.files) files.push_back(load(f));
  std::optional<ScriptPlayer> script;
  if (!options.script.empty()) script.emplace(readViewScript(options.script));
  requireDisplay();

  auto context = gl::Context::window(options.width, options.height, "isoatlas view");
  GLFWwindow* window = context->glfwWindow();
  glfwSwapInterval(options.frames > 0 || script ? 0 : 1);
  ImGuiScope imgui(window);
  ViewerReport report;
  {
    Viewer viewer(*context, options);
    for (Loaded& l : files) viewer.show(std::move(l));
    int shots = 0;
    bool pWasDown = false;
    auto last = std::chrono::steady_clock::now();
    for (int frame = 0; !glfwWindowShouldClose(window); ++frame) {
      glfwPollEvents();
      int width = 0, height = 0;
      glfwGetFramebufferSize(window, &width, &height);
      width = std::max(width, kPanelWidth + 16), height = std::max(height, 16);
      std::string screenshot;
      bool quit = false;
      if (script) script->step(viewer, screenshot, quit);
      viewer.update();
      ImGui_ImplOpenGL3_NewFrame();
      ImGui_ImplGlfw_NewFrame();
      ImGui::NewFrame();
      viewer.handleMouse(window, width, height);
      viewer.handleKeys(window);
      bool shoot = false;
      viewer.drawPanel(width, height, shoot, quit);
      const bool pDown = glfwGetKey(window, GLFW_KEY_P) == GLFW_PRESS;
      shoot |= !ImGui::GetIO().WantCaptureKeyboard && pDown && !pWasDown;
      pWasDown = pDown;
      viewer.drawView(width, height);
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      glViewport(0, 0, width, height);
      ImGui::Render();
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
      const bool lastFrame = options.frames > 0 && frame + 1 >= options.frames;
      if (shoot) writePng("isoatlas_view_" + std::to_string(shots++) + ".png", gl::readWindowImage(width, height));
      if (!screenshot.empty()) writePng(screenshot, gl::readWindowImage(width, height));
      if (lastFrame && !options.screenshot.empty()) writePng(options.screenshot, gl::readWindowImage(width, height));
      glfwSwapBuffers(window);
      const auto now = std::chrono::steady_clock::now();
      const double ms = std::chrono::duration<double, std::milli>(now - last).count();
      last = now;
      ModeFrames& f = report.modes[modeName(viewer.mode())];
      f.meanMs = (f.meanMs * f.frames + ms) / (f.frames + 1);
      f.maxMs = std::max(f.maxMs, ms);
      ++f.frames;
      if (lastFrame || quit) break;
    }
    report.iterations = viewer.iterations();
    report.backend = viewer.backendName();
  }
  return report;
}

}  // namespace isoatlas::viewer
