// The window's state and every action on it (viewer_app.h's window): what each view shows and how it
// is set. The mouse (viewer_input.cpp), the panels (viewer_panels.cpp) and a script
// (view_script.h's ScriptPlayer) all go through Viewer's actions; viewer_drawing.cpp draws it.
// Internal to viewer/.
#pragma once
#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "atlas/atlas_previews.h"
#include "atlas/model_file.h"
#include "core/error.h"
#include "core/gl/context.h"
#include "core/gl/resources.h"
#include "core/image.h"
#include "core/volume_io.h"
#include "core/volume.h"
#include "edit/dvt/volume_tree.h"
#include "extract/gpu_marching_cubes.h"
#include "viewer/brush_edit.h"
#include "viewer/image_panel.h"
#include "viewer/model_job.h"
#include "viewer/segmentation_session.h"
#include "viewer/tree_painting.h"
#include "viewer/viewer_app.h"
#include "render/atlas_render.h"
#include "render/dvt_render.h"
#include "render/orbit.h"
#include "render/scene.h"
#include "render/slice_render.h"
#include "render/volume_render.h"

struct GLFWwindow;

namespace isoatlas::viewer::window {

namespace dvt = edit::dvt;

constexpr int kPanelWidth = kControlsWidth;

enum class Mode { Segment, Mesh, Tree };
inline const char* modeName(Mode m) { return m == Mode::Segment ? "segment" : m == Mode::Mesh ? "mesh" : "tree"; }
enum class Tool { Navigate, Probe, SeedIn, SeedOut, Brush };
// The tools by the names scripts give them (view_script.h's `tool`).
inline constexpr std::array<std::pair<const char*, Tool>, 5> kToolNames{
    {{"navigate", Tool::Navigate}, {"probe", Tool::Probe}, {"seed", Tool::SeedIn}, {"unseed", Tool::SeedOut}, {"brush", Tool::Brush}}};
// The tool named `name`; none when no tool has that name.
inline std::optional<Tool> toolNamed(const std::string& name) {
  for (const auto& [n, tool] : kToolNames)
    if (name == n) return tool;
  return std::nullopt;
}
enum class BrushShape { Sphere, Box, Capsule };

// A file as read before any window opens, so that a bad one is one line.
struct Loaded {
  std::string file;
  std::optional<Volume> volume;
  std::optional<atlas::Model> model;
  std::optional<dvt::VolumeTree> tree;
};
Loaded load(const std::string& file, const VolumeReadOptions& read = {});  // read: a volume's --volume, --series

// The voxel axis a slice panel is normal to: k for the axial (0), j the coronal (1), i the sagittal (2).
inline int sliceNormalAxis(int panel) { return 2 - panel; }

struct SegmentView {
  std::unique_ptr<SegmentationSession> session;
  std::string file;
  render::IntensityWindow window;
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
  std::unique_ptr<render::VolumeRenderer> volume;
  std::unique_ptr<gl::Framebuffer> volumeTarget;
  // The level set's pages as the volume renderer reads them, made again only when phi changes (an
  // orbit or a new T or eps redraws from the same; on the CPU backend making them uploads the pool).
  std::unique_ptr<levelset::PagedPhiGpu> pagedPhi;
  std::uint64_t pagedPhiVersion = ~0ull;
  ImagePanel surface;
  // On a GPU level set, the surface is marched where phi lies and drawn from the buffers it is left
  // in, which persist from one picture to the next.
  std::unique_ptr<extract::GpuMarchingCubes> marching;
  std::uint64_t view3dVersion = ~0ull;
  bool view3dDirty = true;
  std::chrono::steady_clock::time_point view3dAt;
  render::Orbit orbit;
  render::Camera camera3d;  // the volume rendering's, for picking
  std::optional<render::ClipPlane> clip() const {
    if (clipAxis < 0) return std::nullopt;
    Vec3 n{0, 0, 0};
    n[clipAxis] = clipAbove ? 1 : -1;
    return render::ClipPlane{point, n};
  }
};

struct ModelView {
  std::string name;
  atlas::Model model;
  std::unique_ptr<render::Scene> scene;
  int cpuLevel = 2, gpuHalvings = 1;
  bool viewDependent = false, wire = false, chartColours = false, grid = false;
  ImagePanel atlasPreview;
  render::Orbit orbit;
  // The last frame's camera and GPU refinement, for picking what it drew.
  render::Camera camera;
  render::GpuRefinement gpu;
  // The stamp tool: a word pressed into the surface where the mouse picks it.
  char stampWord[64] = "isoatlas";
  float stampRadius = 10, stampDepth = 0.8f;
  // The scene again (after the grid switch, or a stamp changed the atlas the scene uploaded).
  void rebuild() {
    scene = std::make_unique<render::Scene>(std::vector<const atlas::Model*>{&model});
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
  render::Orbit orbit;
  render::Camera camera;  // the last frame's, for picking
  // The brush (ctrl-drag on the view, or a script's stroke in tree mode): the tree being painted,
  // drawn from its own buffers once the first dab is made; `tree` is taken from it when a stroke
  // ends (picking reads `tree`, so a stroke paints over the surface as it was when it began).
  std::unique_ptr<TreePainting> painting;
  float brushRadius = 1;  // world units: 4 voxels when the tree is shown
  bool brushUnion = true, stroking = false;
  Vec3 lastDab;
  // A script's stroke, a dab a frame (so that each dab's picture is drawn, and timed, before the next).
  std::deque<Vec3> scriptedDabs;
  double scriptedRadius = 0;  // > 0 while a script's stroke lasts
  bool scriptedAdd = true;
};

// The window's state and every action on it; the mouse, the panels and the script all go through these.
class Viewer {
public:
  // Draws into the current GL context (the window's), as every renderer of render/ does.
  explicit Viewer(const ViewerOptions& options);

  // ---- actions (throw Error on bad input; the panels show it, the script stops with it) ----
  void show(Loaded loaded);
  const VolumeReadOptions& readOptions() const;  // the command's --volume and --series, for every volume it opens
  void setMode(const std::string& name);
  void slice(const Vec3& p);
  void probe(const Vec3& p, double radius);
  void seed(const Vec3& p, double radius, bool add);
  void set(const std::string& parameter, double value);  // t, eps or alpha
  void setTopology(const std::string& word);              // free or preserve
  void fillThreads();
  // What a click on the slices does: navigate, probe, seed, unseed or brush (carving; the panel's
  // "brush adds" makes it add).
  void setTool(const std::string& name);
  void run(int steps) { seg().session->requestSteps(steps); }
  void undo();
  void redo();
  // A brush stroke: begun with the tree of the segmentation, dabs as the mouse moves (or as a script
  // lists them), ended with its mask as the segmentation (one undo takes the whole stroke back).
  void beginStroke(bool add, int levels);
  void strokeWith(const dvt::Solid& shape);
  void strokeTo(const Vec3& at, double radius);
  void endStroke();
  void brush(const std::string& shape, bool add, int levels = 0);  // one stroke of a shape `isoatlas edit` takes
  // A sphere brush of `radius` mm dragged through `points`; with `sliceAxis` (0 i, 1 j, 2 k) only in
  // the slice of voxels normal to that axis through the first point. In tree mode it paints the open
  // tree, a dab a frame (busy() until the last is drawn).
  void stroke(const std::vector<Vec3>& points, double radius, bool add, int sliceAxis = -1);
  // The tree view's brush: one dab (the first begins a stroke), and the stroke's end (the tree collapsed).
  void treeDab(const Vec3& at, double radius, bool add);
  void endTreeStroke();
  // Each tree dab's latency, ms: from the dab's write to its picture drawn (glFinish after the frame's blit).
  const std::vector<double>& treeDabLatencies() const { return treeDabMs_; }
  void build();  // extracts the surface and builds the model in the background
  void view3d(bool volume);
  // "off", or the axis and the side cut away: "+x" cuts what lies at larger x than the slice point.
  void clip(const std::string& how);
  void levels(int cpu, int gpu);
  void wireframe(bool on) { mod().wire = on; }
  // A word pressed `depth` mm into the model's surface nearest `at`, fitting a disc of `radius` mm.
  void stamp(const Vec3& at, const std::string& word, double radius, double depth);
  void treeRender(bool cubes);
  void loadMask(const std::string& path);  // the segmentation replaced (one undo takes it back)
  void saveMask(const std::string& path);
  void saveModel(const std::string& path);
  void saveTree(const std::string& path);  // the tree view's, as painted

  // ---- the frame ----
  // Takes the finished build, steps the solver within the frame's budget.
  void update();
  bool busy() const { return (segment_ && segment_->session->running()) || job_ || (tree_ && tree_->scriptedRadius > 0); }
  // An error the last build, or a script's stroke in tree mode, left for the script, once ("build: ...").
  std::string takeDeferredError() { return std::exchange(deferredError_, {}); }
  Mode mode() const { return mode_; }
  int iterations() const { return segment_ ? segment_->session->iterations() : 0; }
  const std::string& status() const { return status_; }
  std::optional<Vec3> slicePoint() const { return segment_ ? std::optional<Vec3>(segment_->point) : std::nullopt; }
  std::string backendName() const { return segment_ ? segment_->session->levelSet().backendName() : ""; }

  // viewer_panels.cpp: the controls on the right.
  void drawPanel(int width, int height, bool& screenshot, bool& quit);
  // viewer_drawing.cpp: the views left of the controls.
  void drawView(int width, int height);
  // viewer_input.cpp: the mouse on the views (the tools, the brush, orbiting, stamping) and the keys.
  void handleMouse(GLFWwindow* window, int width, int height);
  // Ctrl+Z undoes the last edit of the segmentation, Ctrl+Y (or Ctrl+Shift+Z) redoes it.
  void handleKeys(GLFWwindow* window);

private:
  SegmentView& seg() {
    require(bool(segment_), "no volume is open (open one to segment it)");
    return *segment_;
  }
  ModelView& mod() {
    require(bool(model_), "no model is open (open a .isoatlas or build one)");
    return *model_;
  }
  void showModel(atlas::Model model, const std::string& name);
  void showTree(dvt::VolumeTree tree, const std::string& name);
  // UI calls: an error becomes the status line.
  template <class F>
  void attempt(F&& f) {
    try {
      f();
    } catch (const std::exception& e) {
      status_ = e.what();
    }
  }
  void segmentPanel();
  void modelPanel();
  void drawSegment(int width, int height);
  Image surfacePicture(int width, int height);
  std::unique_ptr<dvt::DistanceSolid> brushSolid(const Vec3& at) const;
  std::optional<Vec3> pick3d(double x, double y) const;
  void applyTool(const Vec3& at);
  void brushAt(const Vec3& at);

  const bool softwareGl_;  // llvmpipe: the window draws less by default
  const ViewerOptions& options_;
  levelset::Backend backend_;
  // Compiled when a tree or a model is first drawn, not when the window opens.
  std::optional<render::DvtRenderer> dvtRenderer_;
  std::optional<render::AtlasRenderer> atlasRenderer_;
  render::DvtRenderer& dvtRenderer() { return dvtRenderer_ ? *dvtRenderer_ : dvtRenderer_.emplace(); }
  render::AtlasRenderer& atlasRenderer() { return atlasRenderer_ ? *atlasRenderer_ : atlasRenderer_.emplace(); }
  std::optional<SegmentView> segment_;
  std::optional<ModelView> model_;
  std::optional<TreeView> tree_;
  std::unique_ptr<ModelJob> job_;
  std::unique_ptr<gl::Framebuffer> target_;
  Mode mode_ = Mode::Segment;
  std::string status_, deferredError_;
  std::optional<std::chrono::steady_clock::time_point> treeDabAt_;  // a dab whose picture is not yet drawn
  std::vector<double> treeDabMs_;
  char pathField_[256] = "";
  bool leftWasDown_ = false, zWasDown_ = false, yWasDown_ = false;
  double lastX_ = 0, lastY_ = 0;
};


}  // namespace isoatlas::viewer::window
