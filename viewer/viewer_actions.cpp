// The window's actions (viewer_state.h): each changes the state the next frame draws.
#include "viewer/viewer_state.h"

#include <cstdio>

#include "atlas/stamp_detail.h"
#include "core/gz_file.h"
#include "core/text.h"
#include "core/volume_io.h"
#include "extract/extract_surface.h"
#include "edit/dvt/dvt_file.h"

namespace isoatlas::viewer::window {
namespace {

std::string formatPoint(const Vec3& p) {
  char text[96];
  std::snprintf(text, sizeof text, "%.1f,%.1f,%.1f", p.x, p.y, p.z);
  return text;
}

}  // namespace

Loaded load(const std::string& file, const VolumeReadOptions& read) {
  Loaded l{.file = file};
  if (endsWith(file, ".isoatlas"))
    l.model = atlas::readModel(file);
  else if (endsWith(file, ".dvt"))
    l.tree = dvt::readDvt(file);
  else
    l.volume = readVolume(file, read);
  return l;
}

Viewer::Viewer(const ViewerOptions& options)
    : softwareGl_(gl::Context::current().info().software()), options_(options), backend_(levelset::backendFor(options.backend, softwareGl_)) {}

const VolumeReadOptions& Viewer::readOptions() const { return options_.read; }

void Viewer::show(Loaded loaded) {
  if (loaded.volume) {
    segment_.emplace();
    segment_->file = loaded.file;
    segment_->range = valueRange(*loaded.volume);
    segment_->point = render::volumeCentre(*loaded.volume);
    segment_->session = std::make_unique<SegmentationSession>(std::move(*loaded.volume), backend_);
    segment_->window = segment_->session->window();
    segment_->volume = std::make_unique<render::VolumeRenderer>();
    segment_->volume->setSource(segment_->session->source());
    segment_->volumeRendering = !softwareGl_;  // llvmpipe takes seconds a picture
    mode_ = Mode::Segment;
  } else if (loaded.model) {
    showModel(std::move(*loaded.model), loaded.file);
  } else if (loaded.tree) {
    showTree(std::move(*loaded.tree), loaded.file);
  }
}

void Viewer::setMode(const std::string& name) {
  const Mode m = name == "segment" ? Mode::Segment : name == "mesh" ? Mode::Mesh : Mode::Tree;
  require(m != Mode::Segment || segment_, "mode segment: open a volume first");
  require(m != Mode::Mesh || model_, "mode mesh: open a model (.isoatlas) or build one from the segmentation first");
  require(m != Mode::Tree || tree_, "mode tree: open a tree (.dvt) or brush the segmentation first");
  mode_ = m;
}

void Viewer::slice(const Vec3& p) {
  seg().point = p;
  seg().slicesDirty = seg().view3dDirty = true;
}

void Viewer::probe(const Vec3& p, double radius) {
  const auto r = seg().session->probe(p, radius);
  status_ = "probe at " + formatPoint(p) + ": T " + std::to_string(r.mean) + ", eps " + std::to_string(r.std);
}

void Viewer::seed(const Vec3& p, double radius, bool add) {
  seg().session->seed(p, radius, add);
  status_ = std::string(add ? "seed" : "unseed") + " at " + formatPoint(p);
}

void Viewer::set(const std::string& parameter, double value) {
  levelset::SpeedParams p = seg().session->params();
  (parameter == "t" ? p.target : parameter == "eps" ? p.width : p.alpha) = float(value);
  seg().session->setParams(p);
}

void Viewer::setTopology(const std::string& word) {
  seg().session->setTopology(levelset::topologyFor(word));
  status_ = "topology " + word;
}

void Viewer::fillThreads() {
  status_ = "filled " + std::to_string(seg().session->fillThreads()) + " voxels of threads";
}

void Viewer::setTool(const std::string& name) {
  const std::optional<Tool> tool = toolNamed(name);
  require(tool.has_value(), "tool " + name + ": navigate, probe, seed, unseed or brush");
  seg().tool = *tool;
}

void Viewer::undo() {
  require(seg().session->canUndo(), "undo: nothing to undo");
  seg().session->undo();
}

void Viewer::redo() {
  require(seg().session->canRedo(), "redo: nothing to redo");
  seg().session->redo();
}

void Viewer::beginStroke(bool add, int levels) {
  seg().session->pause();  // the stroke's mask replaces the segmentation as it was when the stroke began
  seg().stroke = std::make_unique<BrushStroke>(seg().session->levelSet(), add ? dvt::Op::Union : dvt::Op::Subtract,
                                               backend_, levels);
}

void Viewer::strokeWith(const dvt::Solid& shape) {
  seg().stroke->apply(shape);
  seg().slicesDirty = true;
}

void Viewer::strokeTo(const Vec3& at, double radius) {
  seg().stroke->dabTo(at, radius);
  seg().slicesDirty = true;
}

void Viewer::endStroke() {
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

void Viewer::brush(const std::string& shape, bool add, int levels) {
  const auto solid = dvt::parseBrush(shape);
  beginStroke(add, levels);
  strokeWith(*solid);
  endStroke();
  status_ = std::string(add ? "union " : "subtract ") + shape + ": " + std::to_string(tree_->tree.nodeCount()) + " nodes";
}

void Viewer::stroke(const std::vector<Vec3>& points, double radius, bool add, int sliceAxis) {
  if (mode_ == Mode::Tree && tree_) {
    require(sliceAxis < 0, "paint: a 2D brush paints a segmentation's slice; in tree mode use stroke");
    require(radius > 0, "stroke: the brush's radius must be > 0");
    tree_->scriptedDabs.assign(points.begin(), points.end());
    tree_->scriptedRadius = radius, tree_->scriptedAdd = add;
    return;
  }
  beginStroke(add, 0);
  if (sliceAxis >= 0) seg().stroke->keepToSlice(sliceAxis, points.front());
  for (const Vec3& p : points) strokeTo(p, radius);
  endStroke();
}

void Viewer::treeDab(const Vec3& at, double radius, bool add) {
  require(bool(tree_), "stroke: no tree is open");
  TreeView& t = *tree_;
  if (!t.painting) t.painting = std::make_unique<TreePainting>(t.tree, backend_);
  treeDabAt_ = std::chrono::steady_clock::now();
  t.painting->dabTo(at, radius, add);
  t.stroking = true, t.lastDab = at;
}

void Viewer::endTreeStroke() {
  TreeView& t = *tree_;
  t.stroking = false, t.scriptedRadius = 0;
  t.scriptedDabs.clear();
  if (!t.painting) return;
  const std::size_t dabs = t.painting->dabs();
  t.painting->endStroke();
  t.tree = t.painting->tree();
  status_ = "painted " + std::to_string(dabs) + (dabs == 1 ? " dab" : " dabs") + " on the " + t.painting->backend() + ": " +
            std::to_string(t.tree.nodeCount()) + " nodes";
}

void Viewer::build() {
  require(bool(options_.buildModel), "build: this window was opened without the model builder");
  require(!job_, "build: a model is being built already");
  SegmentationSession& s = *seg().session;
  require(s.activePages() > 0, "build: the segmentation is empty (seed it first)");
  Mesh surface = extract::extractLevelSet(s.levelSet(), {.largestComponents = 1, .backend = backend_});
  require(surface.faceCount() > 0, "build: the segmentation has no surface");
  job_ = std::make_unique<ModelJob>(std::move(surface), options_.buildModel);
  status_ = "building the model";
}

void Viewer::view3d(bool volume) {
  seg().volumeRendering = volume;
  seg().view3dDirty = true;
}

void Viewer::clip(const std::string& how) {
  SegmentView& s = seg();
  s.clipAxis = how == "off" ? -1 : how[1] - 'x';
  s.clipAbove = how[0] == '+';
  s.view3dDirty = true;
}

void Viewer::levels(int cpu, int gpu) {
  mod().cpuLevel = cpu, mod().gpuHalvings = gpu;
  mod().viewDependent = false;
}

void Viewer::stamp(const Vec3& at, const std::string& word, double radius, double depth) {
  ModelView& m = mod();
  const atlas::StampStats st =
      atlas::stampDetail(m.model.base, m.model.atlas, {.image = renderText(word, 128), .at = at, .radius = radius, .depth = depth});
  require(st.texelsChanged + st.detailTexelsChanged > 0, "stamp: the word reaches no part of the surface there");
  m.rebuild();
  status_ = "stamped \"" + word + "\" on " + std::to_string(st.detailTiles) + " tiles";
}

void Viewer::treeRender(bool cubes) {
  require(bool(tree_), "render: no tree is open");
  tree_->cubes = cubes;
}

void Viewer::loadMask(const std::string& path) {
  seg().session->replaceMask(readVolume(path));
  status_ = "loaded " + path;
}

void Viewer::saveMask(const std::string& path) {
  seg().session->saveMask(path);
  status_ = "saved " + path;
}

void Viewer::saveModel(const std::string& path) {
  atlas::writeModel(path, mod().model);
  status_ = "saved " + path;
}

void Viewer::saveTree(const std::string& path) {
  require(bool(tree_), "save-tree: no tree is open");
  require(!tree_->stroking, "save-tree: a stroke is being painted");
  dvt::writeDvt(path, tree_->tree);
  status_ = "saved " + path;
}

void Viewer::update() {
  if (job_ && job_->done()) {
    std::unique_ptr<ModelJob> job = std::move(job_);
    try {
      showModel(job->take(), "built from " + seg().file);
      status_ = "model built in " + std::to_string(int(job->seconds())) + " s";
    } catch (const std::exception& e) {
      deferredError_ = std::string("build: ") + e.what();
      status_ = std::string("build failed: ") + e.what();
    }
  }
  if (segment_) segment_->session->advance(25);
  if (tree_ && tree_->scriptedRadius > 0) {  // a script's stroke: a dab a frame, ended once the last is drawn
    TreeView& t = *tree_;
    if (t.scriptedDabs.empty()) {
      endTreeStroke();
    } else {
      const Vec3 at = t.scriptedDabs.front();
      t.scriptedDabs.pop_front();
      try {
        treeDab(at, t.scriptedRadius, t.scriptedAdd);
      } catch (const std::exception& e) {
        endTreeStroke();
        deferredError_ = std::string("stroke: ") + e.what();
        status_ = deferredError_;
      }
    }
  }
}

void Viewer::showModel(atlas::Model model, const std::string& name) {
  model_.reset();
  model_.emplace();
  model_->name = name;
  model_->model = std::move(model);
  model_->rebuild();
  mode_ = Mode::Mesh;
}

void Viewer::showTree(dvt::VolumeTree tree, const std::string& name) {
  tree_.emplace();
  tree_->name = name;
  tree_->tree = std::move(tree);
  tree_->box = render::insideBounds(tree_->tree);
  tree_->pointers = std::make_unique<gl::Buffer>(gl::Buffer::of(tree_->tree.pointers));
  tree_->cells = std::make_unique<gl::Buffer>(gl::Buffer::of(tree_->tree.cells));
  const Vec3& h = tree_->tree.frame.spacing;
  tree_->brushRadius = float(4 * std::min({h.x, h.y, h.z}));
  mode_ = Mode::Tree;
}

}  // namespace isoatlas::viewer::window
