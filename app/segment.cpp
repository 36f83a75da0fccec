// isoatlas segment: the paged narrow-band level-set segmentation of a volume from seeds or a mask.

#include "app/command.h"
#include "app/options.h"
#include "levelset/page_manager.h"
#include "pipeline/segmentation.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/mapped_nifti.h"
#include "core/volume_io.h"
#include "levelset/level_set.h"

namespace isoatlas::app {

struct SegmentOptions {
  std::string volume, seedMask, output, phi, backend = "auto", topology = "free";
  VolumeReadOptions read;  // --volume, --series
  std::vector<std::string> seeds;
  double target = 0, width = 0, alpha = pipeline::kDefaultAlpha;
  int iterations = levelset::RunOptions{}.maxIterations, page = levelset::LevelSetOptions{}.pageSize;
  bool converge = false, halfResolutionStart = false;
};

void addSegmentCommand(CLI::App& app, int& exitCode) {
  auto* sub = app.add_subcommand("segment", "segment a structure with the paged narrow-band level-set solver");
  auto o = std::make_shared<SegmentOptions>();
  sub->add_option("volume", o->volume, "input volume (NIfTI, NRRD, INR, or a DICOM folder)")->required();
  addVolumeReadOptions(*sub, o->read);
  sub->add_option("--seed", o->seeds, "seed sphere X,Y,Z[,R] in voxel indices, R in voxels (default " + std::to_string(int(pipeline::kDefaultSeedRadius)) + "); repeatable");
  sub->add_option("--seed-mask", o->seedMask, "start from this mask (same grid; voxels > 0 inside)");
  sub->add_option("--target,-T", o->target, "T: the intensity to segment (isoatlas probe suggests it)")->required()->check(inRange(-kMaxIntensity, kMaxIntensity));
  sub->add_option("--width,-e", o->width, "eps: intensities within T +- eps grow the model")->required()->check(inRange(kMinWidth, kMaxIntensity));
  sub->add_option("--alpha,-a", o->alpha, "weight of the intensity term against curvature (1: intensity only)")
      ->capture_default_str()
      ->check(inRange(0, 1));
  sub->add_option("--iterations,-n", o->iterations, "iterations to run (with --converge, the most; run stops at convergence always, so its cap is higher)")
      ->capture_default_str()
      ->check(inRange(1, kMaxIterations));
  sub->add_flag("--converge", o->converge, "stop early once the front stops moving");
  sub->add_flag("--half-resolution-start", o->halfResolutionStart,
                "with --converge, start from the solution at half resolution instead of the seeds (faster)")
      ->needs("--converge");
  sub->add_option("--backend", o->backend, "gpu, cpu or auto (the GPU when there is one)")->capture_default_str()->check(backendChoice());
  addTopologyOption(*sub, o->topology);
  sub->add_option("--page", o->page, "page size in voxels (a power of two, 4..32)")->capture_default_str()->check(inRange(4, 32));
  sub->add_option("-o,--output", o->output, "output mask (uint8, 1 inside), e.g. mask.nii.gz")->required()->check(outputFile());
  sub->add_option("--phi", o->phi, "also write the level set phi (float, > 0 inside, voxel units)")->check(outputFile());
  bindAction(*sub, [o](nlohmann::json& r) {
    volumeWriteFormatOf(o->output);  // throws for a name that is no volume format to write, before any work
    if (!o->phi.empty()) volumeWriteFormatOf(o->phi);
    require(!o->seeds.empty() || !o->seedMask.empty(), "give at least one --seed X,Y,Z[,R] or a --seed-mask");
    levelset::topologyFor(o->topology);  // a wrong word before any work
    require(levelset::isPageSize(o->page), "--page " + std::to_string(o->page) + ": a power of two from 4 to " +
                                               std::to_string(levelset::kMaxPageSize));
    const levelset::SpeedParams params{float(o->target), float(o->width), float(o->alpha)};
    levelset::validateParams(params);
    std::vector<pipeline::Ball> seeds;
    for (const std::string& s : o->seeds) seeds.push_back(parseBall(s, "--seed", pipeline::kDefaultSeedRadius));
    // An uncompressed NIfTI is read in place, page by page as the band reaches it (core/mapped_nifti.h).
    bool mapped = false;
    const std::shared_ptr<const VolumeSource> source = openVolumeSource(o->volume, o->read, &mapped);
    const Volume& volume = source->geometry();
    for (std::size_t k = 0; k < seeds.size(); ++k) pipeline::requireInside(volume, seeds[k].centre, "--seed " + o->seeds[k]);
    Volume seedMask;
    if (!o->seedMask.empty()) {
      seedMask = readVolume(o->seedMask);
      require(seedMask.dims == volume.dims, o->seedMask + ": its dimensions differ from " + o->volume + "'s");
    }

    const pipeline::Gpu gpu = pipeline::chooseBackend(o->backend);  // before the level set: its context outlives it
    const pipeline::Segmentation s = pipeline::segmentVolume(source, {.params = params,
                                                  .seeds = seeds,
                                                  .seedMask = o->seedMask.empty() ? nullptr : &seedMask,
                                                  .backend = gpu.backend,
                                                  .renderer = gpu.renderer,
                                                  .pageSize = o->page,
                                                  .maxIterations = o->iterations,
                                                  .untilConverged = o->converge,
                                                  .readPhi = !o->phi.empty(),
                                                  .halfResolutionStart = o->halfResolutionStart,
                                                  .topology = levelset::topologyFor(o->topology)});
    writeVolume(o->output, s.mask);
    if (!o->phi.empty()) writeVolume(o->phi, s.phi);

    r.update(s.figures());
    r["steps_per_second"] = s.stats.seconds > 0 ? s.stats.iterations / s.stats.seconds : 0.0;
    r["active_pages_final"] = std::int64_t(s.levelSet->pages().activePages().size());
    r["readback_bytes_per_iteration"] = s.stats.bytesReadBackPerIteration;
    r["gl_contexts"] = gl::Context::made();
    r["volume_read"] = mapped ? "in place (mapped)" : "into memory";
    r["params"] = {{"target", o->target}, {"width", o->width}, {"alpha", o->alpha}, {"page", o->page}};
    logInfo("segment: " + std::to_string(s.insideVoxels) + " voxels inside after " + std::to_string(s.stats.iterations) +
            " iterations (" + (s.stats.converged ? "converged" : "not converged") + "), " + o->output);
    return 0;
  }, exitCode);
}

}  // namespace isoatlas::app
