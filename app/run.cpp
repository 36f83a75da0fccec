// isoatlas run: the main job, volume to model, writing every product and an index.html into one
// folder. Stages that are not built yet are skipped and named as skipped; nothing is faked.
#include <chrono>
#include <filesystem>
#include <sstream>
#include <functional>
#include <future>
#include <optional>

#include "app/command.h"
#include "pipeline/surface_figures.h"
#include "pipeline/demo.h"
#include "pipeline/model_building.h"
#include "pipeline/run_page.h"
#include "app/options.h"
#include "pipeline/segmentation.h"
#include "pipeline/volume_editing.h"
#include "levelset/solids/volume_solid.h"
#include "viewer/dvt_render.h"
#include "levelset/level_set.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image.h"
#include "atlas/atlas_previews.h"
#include "atlas/reconstruct.h"
#include "core/mesh_io.h"
#include "extract/extract_surface.h"
#include "core/progress.h"
#include "core/volume_io.h"
#include "viewer/mesh_render.h"
#include "viewer/scene.h"
#include "viewer/slice_render.h"

namespace isoatlas::app {
namespace {

using pipeline::kDemoSeedRadius;

struct RunOptions {
  std::vector<std::string> seeds;
  double target = 0, width = 1, alpha = 0.8;
  std::string backend = "auto";
  int iterations = 3000;  // the demo converges in under a thousand
  bool halfResolutionStart = false;
  pipeline::ModelRequest model;
  int chart = 33;
  std::string levels = "even";  // the levels run measures: "even" (0, 2, ..., the whole chart) or eval's form
  std::shared_ptr<std::vector<pipeline::EditStep>> edits = std::make_shared<std::vector<pipeline::EditStep>>();
};

// A view-window script (docs/view-script.md) doing what run did, seen in the window: the same
// parameters and segmentation, the same edits as brushes, then the model built. The segmentation is
// the seeds and steps (the same solver: the same segmentation), or, where it started at half
// resolution (startedFrom: its mask's file), that mask.
void writeViewSession(const std::string& path, const std::string& input, const Volume& volume, const levelset::SpeedParams& params,
                      const std::vector<pipeline::Ball>& seeds, int iterations, const std::string& startedFrom,
                      const std::vector<pipeline::EditStep>& edits) {
  std::ostringstream out;
  out.precision(7);  // floats as they were given; world positions to well under a micrometre
  out << "# isoatlas run's segmentation and edits in the window: isoatlas view --script " << path << "\n"
      << "open " << std::filesystem::absolute(input).string() << "\nset t " << params.target << "\nset eps " << params.width
      << "\nset alpha " << params.alpha << "\n";
  const double mmPerVoxel = std::cbrt(volume.spacing.x * volume.spacing.y * volume.spacing.z);  // as the window's radii
  if (startedFrom.empty()) {
    for (const pipeline::Ball& b : seeds) {
      const Vec3 w = volume.indexToWorld(b.centre);
      out << "seed " << w.x << "," << w.y << "," << w.z << "," << b.radius * mmPerVoxel << "\n";
    }
    out << "run " << iterations << "\n";
  } else {
    out << "# run's segmentation, which started from its solution at half resolution (the window steps at full resolution)\n"
        << "load-mask " << std::filesystem::absolute(startedFrom).string() << "\n";
  }
  for (const pipeline::EditStep& e : edits)
    out << (e.shape.starts_with("mesh:") ? "# (a mesh edit, not a brush) " : "") << "brush "
        << (e.op == levelset::dvt::Op::Union ? "union " : "subtract ") << e.shape << "\n";
  out << "build\n";
  writeFileAtomically(path, out.str());
}

// The model through the tessellation renderer, seen from the left: three levels of detail (CPU
// levels, no GPU refinement), the cascade with its wireframe (tile borders brown), and a turntable.
std::string renderModelViews(const atlas::Model& model, pipeline::RunProducts& products, nlohmann::json& r) {
  const viewer::AtlasRenderer renderer;
  viewer::Scene scene({&model});
  const viewer::Camera camera = viewer::Camera::framing(scene.bounds(), 800, 600, {1, 0, 0});
  const gl::Framebuffer target(camera.width, camera.height);
  const int top = atlas::maxLevel(model.chartSize);
  const viewer::GpuRefinement byView{viewer::GpuRefinement::Mode::Pixels, 0, 16};
  auto frame = [&](const viewer::CpuRefinement& cpu, const viewer::GpuRefinement& gpu, const viewer::DrawStyle& style,
                   const viewer::Camera& c, const std::string& file, const std::string& what) {
    const viewer::FrameReport f = viewer::drawFrame(scene, renderer, cpu, gpu, c, style, target);
    writePng(products.add(file, what, true), target.readImage());
    r["views"].push_back({{"file", file}, {"patches", f.gpu.patches}, {"triangles", f.gpu.triangles}, {"cpu_ms", f.cpu.ms},
                          {"gpu_ms", f.gpu.gpuMs}, {"frame_ms", f.ms}});
  };
  // The finest through the cascade: the CPU at a middle level, the GPU's halvings (two levels each) above it.
  const int middle = std::min(top / 2 / 2 * 2, 4), halvings = (top - middle) / 2;
  for (const int level : {2, middle, top}) {
    const int cpuLevel = level == top ? top - 2 * halvings : level;
    const viewer::GpuRefinement gpu{viewer::GpuRefinement::Mode::Level, level == top ? halvings : 0};
    frame({viewer::CpuRefinement::Mode::Level, cpuLevel}, gpu, {}, camera, "render_level" + std::to_string(level) + ".png",
          "the model tessellated at level " + std::to_string(level) + " (isoatlas render --cpu-level " + std::to_string(cpuLevel) +
              " --gpu-level " + std::to_string(gpu.halvings) + ")");
  }
  viewer::DrawStyle wire;
  wire.wireframe = true;
  const viewer::CpuRefinement byError{viewer::CpuRefinement::Mode::Pixels, 0, 3};
  frame(byError, byView, wire, camera, "render_wire.png",
        "the cascade: the CPU splits to 3 pixels of error, the GPU to 16-pixel segments; tile borders brown, tile interiors blue");
  const int turns = 8;
  viewer::Camera small = camera;
  small.width = 320, small.height = 240;
  const gl::Framebuffer smallTarget(small.width, small.height);
  for (int k = 0; k < turns; ++k) {
    char file[32];
    std::snprintf(file, sizeof file, "turntable_%03d.png", k);
    const viewer::Camera c = small.turned(2 * 3.14159265358979 * k / turns);
    viewer::drawFrame(scene, renderer, byError, byView, c, {}, smallTarget);
    writePng(products.add(file, "turntable frame " + std::to_string(k + 1) + " of " + std::to_string(turns), k == 0), smallTarget.readImage());
  }
  return "levels 2, " + std::to_string(middle) + ", " + std::to_string(top) + ", the wireframe and " +
         std::to_string(turns) + " turntable frames: render_*.png, turntable_*.png";
}

// One run: its input, the process's GL context, what it wrote and the stages it went through (each
// with its seconds), and the report they fill.
struct RunJob {
  std::string input;
  Volume volume;
  pipeline::Gpu gpu;
  pipeline::RunProducts products;
  std::vector<pipeline::RunStage> stages;
  nlohmann::json& report;

  // Runs one stage, timed; `work` returns its detail line.
  void stage(const std::string& name, const std::function<std::string()>& work) {
    const auto start = std::chrono::steady_clock::now();
    std::string detail = work();
    stages.push_back({name, "done", std::move(detail), std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
  }
  void skipped(const std::string& name, const std::string& why) { stages.push_back({name, "skipped", why}); }
};

// The segmentation's seeds and parameters: the user's (--seed, --target, --width, --alpha), or the
// demo's when the input is the demo volume and no seed is given (then the demo's edit too, unless
// the user gave edits).
struct SegmentationSetup {
  std::vector<pipeline::Ball> seeds;
  levelset::SpeedParams params;
  pipeline::EditRequest edits;
};
SegmentationSetup segmentationSetup(const RunOptions& options, const std::string& input, const Volume& volume) {
  SegmentationSetup s{{}, {float(options.target), float(options.width), float(options.alpha)}, {.steps = *options.edits}};
  for (const std::string& text : options.seeds) {
    s.seeds.push_back(parseBall(text, "--seed", kDemoSeedRadius));
    pipeline::requireInside(volume, s.seeds.back().centre, "--seed " + text);
  }
  if (s.seeds.empty() && pipeline::isDemoVolume(input, volume)) {
    for (const Vec3& seed : pipeline::kDemoSeeds) s.seeds.push_back({seed, kDemoSeedRadius});
    s.params = pipeline::kDemoParams;
    if (s.edits.steps.empty()) s.edits.steps.push_back({levelset::dvt::Op::Subtract, pipeline::kDemoEdit});
  }
  return s;
}

pipeline::Segmentation segmentStage(RunJob& job, const SegmentationSetup& setup, int iterations, bool halfResolutionStart) {
  std::optional<pipeline::Segmentation> result;
  job.stage("segment", [&] {
    result = pipeline::segmentVolume(job.volume, {.params = setup.params,
                                                  .seeds = setup.seeds,
                                                  .backend = job.gpu.backend,
                                                  .renderer = job.gpu.renderer,
                                                  .maxIterations = iterations,
                                                  .label = "run: segment",
                                                  .readPhi = true,
                                                  .halfResolutionStart = halfResolutionStart});
    const pipeline::Segmentation& s = *result;
    const std::string maskFile = job.products.add("mask.nii.gz", "the segmentation: uint8, 1 inside, on the input's grid");
    writeVolume(maskFile, s.mask);
    writeVolume(job.products.add("phi.nii.gz", "the level set phi: float, > 0 inside, in voxels"), s.phi);
    job.report["segment"] = s.figures();
    job.report["segment"].update({{"target", setup.params.target}, {"width", setup.params.width}, {"alpha", setup.params.alpha}});
    writeViewSession(job.products.add("view-session.txt", "this segmentation and its edits replayed in the window: isoatlas view --script "
                                                          "view-session.txt (docs/view-script.md)"),
                     job.input, job.volume, setup.params, setup.seeds, s.stats.iterations,
                     s.halfResolution.iterations > 0 ? maskFile : std::string(), setup.edits.steps);
    return std::to_string(s.insideVoxels) + " voxels in " + std::to_string(s.stats.iterations) + " iterations (" +
           (s.stats.converged ? "converged" : "not converged") + "): mask.nii.gz, phi.nii.gz";
  });
  return std::move(*result);
}

// The edits on a volume tree of the level set's phi (read from its pages). Its picture waits for
// surfacePictures, which runs beside the model's build.
struct EditedVolume {
  std::optional<pipeline::EditedTree> edited;
  std::optional<levelset::dvt::VolumeTree> tree;  // edited->tree's streams, taken once
};
EditedVolume editStage(RunJob& job, const pipeline::Segmentation& s, const pipeline::EditRequest& edits,
                       const std::vector<std::unique_ptr<levelset::dvt::DistanceSolid>>& solids) {
  EditedVolume out;
  if (edits.steps.empty()) {
    job.skipped("edit", "no --union or --subtract given");
    return out;
  }
  job.stage("edit", [&] {
    out.edited = pipeline::treeOfLevelSet(*s.levelSet, edits, job.gpu);
    pipeline::applySteps(*out.edited, edits, solids);
    out.tree = out.edited->tree->tree();
    writeVolume(job.products.add("mask_edited.nii.gz", "the segmentation after the edits: uint8, 1 inside"), levelset::dvt::sampleMask(*out.tree));
    job.report["edit"] = out.edited->figures(*out.tree);
    std::string what;
    for (const pipeline::EditStep& e : edits.steps)
      what += std::string(what.empty() ? "" : ", ") + (e.op == levelset::dvt::Op::Union ? "union " : "subtract ") + e.shape;
    job.report["edit"]["edits"] = what;
    return what + ": " + std::to_string(out.tree->nodeCount()) + " nodes on the " + out.edited->backend + ": mask_edited.nii.gz";
  });
  return out;
}

// Marching cubes over the edited tree's distances; without edits, over the level set's active pages,
// read where the solver keeps them. The surface keeps its largest component.
Mesh extractStage(RunJob& job, const pipeline::Segmentation& s, const EditedVolume& edit) {
  Mesh surface;
  job.stage("extract", [&] {
    extract::ExtractStats stats;
    const extract::ExtractOptions options{.iso = 0.0f, .largestComponent = true, .backend = s.backend};
    surface = edit.tree ? extract::extractSurface(levelset::dvt::sampleField(*edit.tree, edit.tree->frame.voxelDepth()), options, &stats)
                        : extract::extractLevelSet(*s.levelSet, options, &stats);
    writeMesh(job.products.add("surface.ply", "the extracted surface, closed and manifold, in world coordinates (mm)"), surface);
    const nlohmann::json& figures = job.report["extract"] = pipeline::surfaceFigures(surface, &stats);
    return std::to_string(surface.faceCount()) + " triangles, genus " + std::to_string(figures["genus"].get<long long>()) + ", " +
           (figures["closed"].get<bool>() ? "closed" : "NOT closed") + ": surface.ply";
  });
  return surface;
}

// The edited tree ray cast (the edit's picture), then the surface seen from the left (RAS -x) and
// from above, as a reader of an atlas would look, and the segmentation over the input through the
// first seed (so the slices cut the structure). Returns the pictures' names.
std::string surfacePictures(RunJob& job, const EditedVolume& edit, const Mesh& surface, const pipeline::Segmentation& s,
                            const Vec3& firstSeed) {
  job.gpu.needGl();
  std::string names;
  if (edit.tree) {
    const viewer::DvtView view{.camera = viewer::Camera::framing(viewer::insideBounds(*edit.tree), 800, 600, {1, 0.3, -0.3})};
    writePng(job.products.add("edited_tree.png", "the edited segmentation, ray cast straight from the volume tree", true),
             pipeline::renderEditedTree(*edit.edited, *edit.tree, view, job.gpu));
    names = "edited_tree.png, ";
  }
  writePng(job.products.add("surface_left.png", "the extracted surface seen from the left", true),
           viewer::renderMesh(surface, {.viewDirection = {1, 0, 0}}));
  writePng(job.products.add("surface_top.png", "the extracted surface seen from above (anterior up)", true),
           viewer::renderMesh(surface, {.viewDirection = {0, 0, -1}, .up = {0, 1, 0}}));
  viewer::SliceOptions overlay;
  overlay.mask = &s.mask;
  writePng(job.products.add("segmentation_slices.png", "the segmentation over the input, through the first seed", true),
           viewer::renderSlices(job.volume, job.volume.indexToWorld(firstSeed), overlay));
  return names + "surface_left.png, surface_top.png, segmentation_slices.png";
}

// The multiresolution model of the surface (base mesh, atlas), its files and previews, made on a
// thread of its own beside the pictures (so nothing here touches GL or the job): what it wrote is in
// `products`, its figures in `figures`.
struct BuiltModel {
  std::optional<atlas::Model> model;
  nlohmann::json figures;
  pipeline::RunProducts products;
  double seconds = 0;
};
BuiltModel buildModelFiles(const Mesh& surface, const pipeline::ModelRequest& request, const std::filesystem::path& dir) {
  const auto start = std::chrono::steady_clock::now();
  BuiltModel b{.products = {dir, {}}};
  const atlas::Model& model = b.model.emplace(pipeline::buildModel(surface, request, b.figures));
  const std::string path = b.products.add("model.isoatlas", "the multiresolution model: base mesh and atlas of charts (isoatlas eval, render)");
  const pipeline::AtlasPreviewPaths previews{
      b.products.add("position_atlas.png", "the atlas's positions as colours (x, y, z over the surface's box)", true),
      b.products.add("normal_atlas.png", "the atlas's normals as colours", true)};
  pipeline::writeModelFiles(model, path, previews, b.figures);
  b.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return b;
}

// The model's accuracy per level (eval's figures) and its plot, on the same thread.
struct MeasuredLevels {
  std::vector<atlas::LevelFigures> levels;
  pipeline::RunProducts products;
  double seconds = 0;
};
MeasuredLevels measureLevels(const atlas::Model& model, const Mesh& surface, const std::vector<int>& levels, std::size_t facePoints,
                             const std::filesystem::path& dir) {
  const auto start = std::chrono::steady_clock::now();
  MeasuredLevels out{.products = {dir, {}}};
  out.levels = atlas::evaluateLevels(model.base, model.atlas, surface, levels, facePoints);
  writePng(out.products.add("psnr_per_level.png", "the model's accuracy per level: PSNR against the surface (CGAL: from the largest distance, and dashed from the RMS)", true),
           atlas::psnrPlot({{"model", out.levels}}));
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

void addProducts(RunJob& job, const pipeline::RunProducts& products) {
  job.products.all.insert(job.products.all.end(), products.all.begin(), products.all.end());
}

// The built model into the job, with its picture at level 4 (drawn here, where the GL context is);
// the stage's seconds are the build's and the picture's.
void modelStage(RunJob& job, BuiltModel& built, std::uint32_t chartSize) {
  const auto start = std::chrono::steady_clock::now();
  job.report["model"] = std::move(built.figures);
  addProducts(job, built.products);
  const atlas::Model& model = *built.model;
  const int shown = std::min(4, atlas::maxLevel(chartSize));
  job.gpu.needGl();
  writePng(job.products.add("model_level" + std::to_string(shown) + "_left.png",
                            "the model at level " + std::to_string(shown) + " seen from the left (atlas normals)", true),
           viewer::renderMesh(atlas::reconstructLevel(model.base, model.atlas, shown), {.viewDirection = {1, 0, 0}}));
  const double seconds = built.seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  job.stages.push_back({"build multiresolution model", "done",
                        std::to_string(model.base.vertexCount()) + " base vertices, " + std::to_string(model.atlas.layout.charts) +
                            " charts (" + std::to_string(int(model.atlas.layout.efficiency() * 100)) +
                            " % of the atlas): model.isoatlas (built beside the pictures)",
                        seconds});
}

// The levels' figures into the job (eval's, in report.json's model).
void levelsStage(RunJob& job, const MeasuredLevels& measured) {
  nlohmann::json& m = job.report["model"];
  m["seconds_eval"] = measured.seconds;
  m["levels"] = pipeline::levelFiguresJson(measured.levels);
  addProducts(job, measured.products);
  const atlas::LevelFigures& top = measured.levels.back();
  job.stages.push_back({"measure the model's levels", "done",
                        "PSNR " + std::to_string(top.psnrDb) + " dB at level " + std::to_string(top.level) + ": psnr_per_level.png",
                        measured.seconds});
}

// The demo engraves a word on the left hemisphere's lateral surface (fine detail, the paper's Fig. 10).
// The model stands without it: a failure is a skipped stage. The stamp and the engraved model's file
// are made on a thread of their own while this one renders the model (llvmpipe draws its geometry on
// one core); the close-up, which needs the GL context, is drawn here afterwards.
struct Engraving {
  std::optional<atlas::Model> model;
  atlas::StampStats stamped;
  double radius = 0, seconds = 0;
  nlohmann::json figures;
  std::string skipped;  // why not, when it was not made
  bool failed = false;  // the stamp or the file failed (said on stderr), rather than not wanted
};
constexpr const char* kEngraveStage = "engrave a word (fine detail, beside the render)";
constexpr const char* kEngravedModel = "model_engraved.isoatlas";

std::future<Engraving> startEngraving(const atlas::Model& model, const Mesh& surface, const std::filesystem::path& dir) {
  return std::async(std::launch::async, [&model, &surface, dir] {
    const auto start = std::chrono::steady_clock::now();
    const Box box = boundingBox(surface.positions);
    const pipeline::DemoEngraving place = pipeline::demoEngraving(box.min, box.max);
    const pipeline::StampRequest engrave{.text = "isoatlas", .at = place.at, .radius = place.radius, .depth = 1.5,
                                         .detailSize = std::min(multires::kMaxChartSize, 4 * (model.chartSize - 1) + 1)};
    Engraving e{.radius = engrave.radius};
    if (engrave.detailSize <= model.chartSize) {
      e.skipped = "the charts are already the finest (--chart 129)";
      return e;
    }
    try {
      atlas::Model& engraved = e.model.emplace(model);
      e.stamped = pipeline::stampModel(engraved, engrave, e.figures);
      pipeline::writeModelFiles(engraved, (dir / kEngravedModel).string(), {}, e.figures);
    } catch (const Error& error) {
      e.model.reset();
      e.skipped = error.what();
      e.failed = true;
    }
    e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return e;
  });
}

void finishEngraving(RunJob& job, std::future<Engraving>& engraving) {
  Engraving e = engraving.get();
  if (!e.model) {
    job.skipped(kEngraveStage, e.skipped);
    if (e.failed) logInfo("run: skipping the engraving: " + e.skipped);
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  job.report["engrave"] = std::move(e.figures);
  job.products.add(kEngravedModel, "the model with \"isoatlas\" engraved in detail charts (isoatlas edit-detail)");
  try {
    writePng(job.products.add("engraved.png", "the engraved word at the model's finest level, close up", true),
             pipeline::closeUp(*e.model, e.stamped, e.radius));
  } catch (const Error& error) {
    job.skipped(kEngraveStage, error.what());
    logInfo(std::string("run: skipping the engraving's close-up: ") + error.what());
    return;
  }
  job.stages.push_back({kEngraveStage, "done", std::to_string(e.stamped.detailTiles) + " tiles given detail charts: " + kEngravedModel,
                        e.seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
}

// The levels the model's accuracy is measured at: "even" (0, 2, ..., the whole chart) or eval's form.
std::vector<int> runLevels(const std::string& text, int topLevel) {
  if (text != "even") return pipeline::parseLevels(text, topLevel);
  std::vector<int> levels;
  for (int l = 0; l <= topLevel; l += 2) levels.push_back(l);
  return levels;
}

void checkRunOptions(const RunOptions& o) {
  require(o.iterations > 0, "--iterations must be > 0");
  require(o.model.hausdorffFacePoints >= 1000, "--samples must be at least 1000");
  pipeline::ModelRequest model = o.model;  // --base-ratio, --chart, --relax-sweeps: as build checks them
  model.chartSize = o.chart > 0 ? std::uint32_t(o.chart) : 0;
  pipeline::checkModelRequest(model);
  pipeline::stepSolids(*o.edits);  // bad shapes are reported before any work
}

// The whole job, stage by stage; a stage that cannot run is named as skipped.
void runJob(const std::string& input, const std::string& outDir, const RunOptions& options, nlohmann::json& r) {
  const auto start = std::chrono::steady_clock::now();
  checkRunOptions(options);
  const std::vector<int> levels = runLevels(options.levels, atlas::maxLevel(std::uint32_t(options.chart)));
  // Bad input (the volume, a seed outside it, an edit's shape) is refused before anything is written.
  Volume volume = readVolume(input);
  const double secondsRead = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const SegmentationSetup setup = segmentationSetup(options, input, volume);
  const auto solids = pipeline::stepSolids(setup.edits.steps);
  const std::filesystem::path dir(outDir);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  require(!ec, outDir + ": cannot create the output folder: " + ec.message());

  // The process's one GL context: the solver, the extraction from its pages and the renders share it.
  RunJob job{input, std::move(volume), pipeline::chooseBackend(options.backend), {dir, {}}, {}, r};
  const Volume& v = job.volume;
  r["input"] = {{"file", input}, {"dims", {v.dims[0], v.dims[1], v.dims[2]}}, {"spacing", {v.spacing.x, v.spacing.y, v.spacing.z}}};
  job.stages.push_back({"read", "done",
                        std::to_string(v.dims[0]) + " x " + std::to_string(v.dims[1]) + " x " + std::to_string(v.dims[2]) + " " +
                            scalarTypeName(v.type),
                        secondsRead});
  job.stage("render input slices", [&] {
    writePng(job.products.add("input_slices.png", "the input: axial, coronal and sagittal slices through its centre", true),
             viewer::renderSlices(job.volume, viewer::volumeCentre(job.volume)));
    return std::string("input_slices.png");
  });

  if (setup.seeds.empty()) {
    job.skipped("segment", "no --seed given (and the input is not the demo volume)");
    logInfo("run: skipping segment: give --seed X,Y,Z[,R] --target T --width EPS");
    job.skipped("build multiresolution model", "no surface (nothing was segmented)");
  } else {
    const pipeline::Segmentation s = segmentStage(job, setup, options.iterations, options.halfResolutionStart);
    const EditedVolume edit = editStage(job, s, setup.edits, solids);
    const Mesh surface = extractStage(job, s, edit);
    pipeline::ModelRequest request = options.model;
    request.chartSize = std::uint32_t(options.chart);
    // The model is built and measured on a thread of its own while this one, which holds the GL
    // context, draws: most of the simplification runs on one core. (Measuring beside the renders
    // instead gained nothing: each then took as long as both.)
    std::future<std::pair<BuiltModel, MeasuredLevels>> modelling = std::async(std::launch::async, [&] {
      BuiltModel b = buildModelFiles(surface, request, dir);
      MeasuredLevels measured = measureLevels(*b.model, surface, levels, request.hausdorffFacePoints, dir);
      return std::pair{std::move(b), std::move(measured)};
    });
    job.stage("pictures of the edit and the surface (beside the model's build)",
              [&] { return surfacePictures(job, edit, surface, s, setup.seeds.front().centre); });
    auto [built, measured] = modelling.get();
    modelStage(job, built, request.chartSize);
    levelsStage(job, measured);
    const atlas::Model& model = *built.model;
    const bool engrave = pipeline::isDemoVolume(input, job.volume);
    std::future<Engraving> engraving = engrave ? startEngraving(model, surface, dir) : std::future<Engraving>{};
    job.stage("render model (tessellation)", [&] { return renderModelViews(model, job.products, r["render"]); });
    if (engrave) finishEngraving(job, engraving);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r["stages"] = pipeline::stagesJson(job.stages);
  r["gl_contexts"] = gl::Context::made();
  r["seconds"] = seconds;
  r["products"] = pipeline::productsJson(job.products);
  writeJsonFile((dir / "report.json").string(), r);
  pipeline::writeRunPage(dir, input, job.stages, job.products, seconds);
  logInfo("run: wrote " + (dir / "index.html").string());
}

}  // namespace

void addRunCommand(CLI::App& app, int& exitCode) {
  auto* sub = app.add_subcommand("run", "the whole job on a volume: segment, extract, build, render (stages not built yet are skipped)");
  auto input = std::make_shared<std::string>(pipeline::kDemoVolume);
  auto outDir = std::make_shared<std::string>("out/demo");
  auto options = std::make_shared<RunOptions>();
  sub->add_option("volume", *input, "input volume")->capture_default_str();
  sub->add_option("-o,--output", *outDir, "folder for every product and index.html")->capture_default_str();
  sub->add_option("--seed", options->seeds, "seed X,Y,Z[,R] (voxel indices); the demo volume has its own");
  sub->add_option("--target,-T", options->target, "T for the segmentation");
  sub->add_option("--width,-e", options->width, "eps for the segmentation");
  sub->add_option("--alpha,-a", options->alpha, "alpha for the segmentation")->capture_default_str();
  sub->add_option("--backend", options->backend, "gpu, cpu or auto")->capture_default_str();
  sub->add_option("--iterations,-n", options->iterations, "most iterations of the segmentation (it stops once converged)")
      ->capture_default_str();
  sub->add_flag("--half-resolution-start", options->halfResolutionStart,
                "segment from the solution at half resolution instead of the seeds (faster; the window's script then loads the mask)");
  addEditStepOptions(*sub, options->edits);
  sub->add_option("--base-ratio", options->model.baseRatio,
                  "base vertices of the model as a fraction of the surface's (default: 2 % up to 1000 vertices, at least 1 %)");
  sub->add_option("--chart", options->chart, "chart size of the model, 2^k + 1")->capture_default_str();
  sub->add_option("--relax-sweeps", options->model.relaxSweeps,
                  "sweeps moving the model's texels to follow the surface's bending (0: a uniform grid per tile)")
      ->capture_default_str();
  sub->add_option("--samples", options->model.hausdorffFacePoints, "Hausdorff face samples per mesh for the model's accuracy")
      ->capture_default_str();
  sub->add_option("--levels", options->levels, "levels whose accuracy the model's report gives: even, 0-10, 0,4,10")
      ->capture_default_str();
  bindAction(*sub, [input, outDir, options](nlohmann::json& r) {
    runJob(*input, *outDir, *options, r);
    return 0;
  }, exitCode);
}

}  // namespace isoatlas::app
