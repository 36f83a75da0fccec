// isoatlas run: the main job, volume to model, writing every product and an index.html into one
// folder. A stage that cannot run on this input (no seed, no edit) is named as skipped; nothing is faked.
// The options and the order of the stages are here; the stages are in run_stages, the window's script
// in run_view_session, the model's pictures in run_model_views and the demo's engraving in run_engraving.
#include <chrono>
#include <filesystem>
#include <future>
#include <optional>

#include "app/command.h"
#include "app/options.h"
#include "app/run_engraving.h"
#include "app/run_model_views.h"
#include "app/run_stages.h"
#include "atlas/reconstruct.h"
#include "core/error.h"
#include "core/image.h"
#include "core/progress.h"
#include "core/volume_io.h"
#include "multires/base_mesh.h"
#include "pipeline/demo.h"
#include "pipeline/model_building.h"
#include "pipeline/run_page.h"
#include "pipeline/segmentation.h"
#include "pipeline/volume_editing.h"
#include "render/slice_render.h"

namespace isoatlas::app {
namespace {

using pipeline::kDemoSeedRadius;

struct RunOptions {
  std::vector<std::string> seeds;
  std::optional<double> target, width;  // required with --seed, as segment requires them
  double alpha = pipeline::kDefaultAlpha;
  std::string backend = "auto";
  // A cap, as run always stops at convergence: higher than segment's count, which it runs whole
  // without --converge. The demo converges in under a thousand.
  int iterations = 3000;
  bool halfResolutionStart = false;
  std::string topology;  // --topology; empty: the demo's own (preserve) for the demo volume, else free
  std::string space = "ras";  // --space: the surface files' frame
  VolumeReadOptions read;  // --volume, --series
  pipeline::ModelRequest model;
  int chart = 33;
  std::string levels = "even";  // the levels run measures: "even" (0, 2, ..., the whole chart) or eval's form
  std::shared_ptr<std::vector<pipeline::EditStep>> edits = std::make_shared<std::vector<pipeline::EditStep>>();
};

// The segmentation's seeds and parameters: the user's (--seed, --target, --width, --alpha), or the
// demo's when the input is the demo volume and no seed is given (then the demo's edit too, unless
// the user gave edits).
SegmentationSetup segmentationSetup(const RunOptions& options, const std::string& input, const Volume& volume) {
  SegmentationSetup s{{}, {float(options.target.value_or(0)), float(options.width.value_or(1)), float(options.alpha)}, {.steps = *options.edits}, levelset::Topology::Free};
  for (const std::string& text : options.seeds) {
    s.seeds.push_back(parseBall(text, "--seed", pipeline::kDefaultSeedRadius));
    pipeline::requireInside(volume, s.seeds.back().centre, "--seed " + text);
  }
  if (s.seeds.empty() && pipeline::isDemoVolume(input, volume)) {
    for (const Vec3& seed : pipeline::kDemoSeeds) s.seeds.push_back({seed, kDemoSeedRadius});
    s.params = pipeline::kDemoParams;
    if (s.edits.steps.empty()) s.edits.steps.push_back({edit::dvt::Op::Subtract, pipeline::kDemoEdit});
    s.topology = pipeline::kDemoTopology;
  }
  if (!options.topology.empty()) s.topology = levelset::topologyFor(options.topology);
  return s;
}

// The levels the model's accuracy is measured at: "even" (0, 2, ..., the whole chart) or eval's form.
std::vector<int> runLevels(const std::string& text, int topLevel) {
  if (text != "even") return pipeline::parseLevels(text, topLevel);
  std::vector<int> levels;
  for (int l = 0; l <= topLevel; l += 2) levels.push_back(l);
  return levels;
}

void checkRunOptions(const RunOptions& o) {
  require(o.seeds.empty() || (o.target && o.width), "--seed needs --target T and --width EPS (isoatlas probe suggests them)");
  pipeline::ModelRequest model = o.model;  // --base-ratio, --chart, --relax-sweeps: as build checks them
  model.chartSize = o.chart > 0 ? std::uint32_t(o.chart) : 0;
  pipeline::checkModelRequest(model);
  pipeline::stepSolids(*o.edits);  // bad shapes are reported before any work
  if (!o.topology.empty()) levelset::topologyFor(o.topology);  // a wrong word before any work
}

// The whole job, stage by stage; a stage that cannot run is named as skipped.
void runJob(const std::string& input, const std::string& outDir, const RunOptions& options, nlohmann::json& r) {
  const auto start = std::chrono::steady_clock::now();
  checkRunOptions(options);
  const std::vector<int> levels = runLevels(options.levels, atlas::maxLevel(std::uint32_t(options.chart)));
  // Bad input (the volume, a seed outside it, an edit's shape) is refused before anything is written.
  Volume volume = readVolume(input, options.read);
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
             render::renderSlices(job.volume, render::volumeCentre(job.volume)));
    return std::string("input_slices.png");
  });

  if (setup.seeds.empty()) {
    job.skipped("segment", "no --seed given (and the input is not the demo volume)");
    logInfo("run: skipping segment: give --seed X,Y,Z[,R] --target T --width EPS");
    job.skipped("build multiresolution model", "no surface (nothing was segmented)");
  } else {
    const pipeline::Segmentation s = segmentStage(job, setup, options.iterations, options.halfResolutionStart);
    const EditedVolume edit = editStage(job, s, setup.edits, solids);
    const Mesh surface = extractStage(job, s, edit, setup.seeds.size(), meshSpace(options.space));
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
  auto* sub = app.add_subcommand("run", "the whole job on a volume: segment, edit, extract, build, measure, render; every product and index.html in one folder");
  auto input = std::make_shared<std::string>(pipeline::kDemoVolume);
  auto outDir = std::make_shared<std::string>("out/demo");
  auto options = std::make_shared<RunOptions>();
  sub->add_option("volume", *input, "input volume (NIfTI, NRRD, INR, or a DICOM folder)")->capture_default_str();
  sub->add_option("-o,--output", *outDir, "folder for every product and index.html")->capture_default_str();
  addVolumeReadOptions(*sub, options->read);
  sub->add_option("--seed", options->seeds, "seed X,Y,Z[,R] in voxel indices, R in voxels (default " + std::to_string(int(pipeline::kDefaultSeedRadius)) + "); the demo volume has its own");
  sub->add_option("--target,-T", options->target, "T for the segmentation, required with --seed (without --seed, the demo volume has its own)")
      ->check(inRange(-kMaxIntensity, kMaxIntensity));
  sub->add_option("--width,-e", options->width, "eps for the segmentation, required with --seed (without --seed, the demo volume has its own)")
      ->check(inRange(kMinWidth, kMaxIntensity));
  sub->add_option("--alpha,-a", options->alpha, "alpha for the segmentation, as segment's (the demo volume has its own, 0.8)")
      ->capture_default_str()
      ->check(inRange(0, 1));
  sub->add_option("--backend", options->backend, "gpu, cpu or auto")->capture_default_str()->check(backendChoice());
  sub->add_option("--iterations,-n", options->iterations, "most iterations of the segmentation: a cap, as run stops once converged (segment runs its -n whole unless --converge)")
      ->capture_default_str()
      ->check(inRange(1, kMaxIterations));
  sub->add_flag("--half-resolution-start", options->halfResolutionStart,
                "segment from the solution at half resolution instead of the seeds (faster; the window's script then loads the mask)");
  addTopologyOption(*sub, options->topology, " (default: preserve for the demo volume without --seed, else free)");
  addEditStepOptions(*sub, options->edits);
  addMeshSpaceOption(*sub, options->space);
  sub->add_option("--base-ratio", options->model.baseRatio,
                  "base vertices of the model as a fraction of the surface's (default: 2 % up to 1000 vertices, at least 1 %)")
      ->check(inRange(1e-6, 1));
  sub->add_option("--chart", options->chart, "chart size of the model, 2^k + 1")->capture_default_str()->check(inRange(3, multires::kMaxChartSize));
  sub->add_option("--relax-sweeps", options->model.relaxSweeps,
                  "sweeps moving the model's texels to follow the surface's bending (0: a uniform grid per tile; "
                  "default 8, and 0 for a mesh that is its own base)")
      ->check(inRange(0, 1000));
  sub->add_option("--samples", options->model.hausdorffFacePoints, "Hausdorff face samples per mesh for the model's accuracy")
      ->capture_default_str()
      ->check(inRange(kMinSamples, kMaxSamples));
  sub->add_option("--levels", options->levels, "levels whose accuracy the model's report gives: even, 0-10, 0,4,10")
      ->capture_default_str();
  bindAction(*sub, [input, outDir, options](nlohmann::json& r) {
    runJob(*input, *outDir, *options, r);
    return 0;
  }, exitCode, outDir);
}

}  // namespace isoatlas::app
