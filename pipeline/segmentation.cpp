#include "pipeline/segmentation.h"

#include <chrono>

#include "core/error.h"
#include "core/progress.h"
#include "levelset/fill_threads.h"
#include "pipeline/coarse_start.h"

namespace isoatlas::pipeline {

void requireTopologyWithStart(levelset::Topology topology, bool halfResolutionStart) {
  require(!halfResolutionStart || topology == levelset::Topology::Free,
          "--half-resolution-start with --topology preserve: the start from half resolution does not keep the seeds' topology; leave one out");
}

Segmentation segmentVolume(const Volume& volume, const SegmentationRequest& request) {
  Segmentation s;
  s.backend = request.backend;
  s.renderer = request.renderer;
  s.topology = request.topology;
  requireTopologyWithStart(request.topology, request.halfResolutionStart);
  s.levelSet = std::make_unique<levelset::LevelSet>(
      volume, request.params, levelset::LevelSetOptions{.backend = s.backend, .pageSize = request.pageSize, .topology = request.topology});
  const auto start = std::chrono::steady_clock::now();
  // One progress line a run: iterations out of the most allowed.
  auto runOptions = [&](Progress& progress) {
    return levelset::RunOptions{.maxIterations = request.maxIterations,
                                .untilConverged = request.untilConverged,
                                .progress = [&progress](int i, std::int64_t) { progress.update(std::uint64_t(i)); }};
  };
  require(!request.halfResolutionStart || request.untilConverged, "the half-resolution start needs the run until converged (--converge)");
  if (request.halfResolutionStart) {
    Progress progress(request.label + " at half resolution", std::uint64_t(request.maxIterations), "iterations");
    CoarseStart coarse = solveAtHalfResolution(volume, request.params, request.seeds, request.seedMask,
                                               {.backend = s.backend, .pageSize = request.pageSize}, runOptions(progress));
    progress.finish();
    s.halfResolution = coarse.stats;
    s.levelSet->setMask(coarse.mask);
  } else {
    if (request.seedMask) s.levelSet->setMask(*request.seedMask);
    for (const Ball& b : request.seeds) s.levelSet->addSphere(b.centre, b.radius);
  }
  Progress progress(request.label, std::uint64_t(request.maxIterations), "iterations");
  s.stats = s.levelSet->run(runOptions(progress));
  progress.finish();
  if (request.topology == levelset::Topology::Preserve) {
    // The threads of background the held voxels leave (fill_threads.h) filled, and the front run on
    // from there (phi is rebuilt from the mask).
    Volume mask = s.levelSet->mask();
    s.threadVoxelsFilled = levelset::fillThreads(mask);
    if (s.threadVoxelsFilled > 0) {
      s.levelSet->setMask(mask);
      Progress again(request.label + " (threads filled)", std::uint64_t(request.maxIterations), "iterations");
      const levelset::RunStats more = s.levelSet->run(runOptions(again));
      again.finish();
      s.stats.iterations += more.iterations;
      s.iterationsAfterFill = more.iterations;
      s.stats.seconds += more.seconds;
      s.stats.simulatedTime += more.simulatedTime;
      s.stats.converged = more.converged;
    }
  }
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (request.readPhi) {
    s.phi = s.levelSet->phi();
    s.mask = levelset::maskOf(s.phi);
  } else {
    s.mask = s.levelSet->mask();
  }
  for (std::size_t n = 0; n < s.mask.voxelCount(); ++n) s.insideVoxels += s.mask.data[n] != std::byte{0};
  return s;
}

nlohmann::json Segmentation::figures() const {
  return {{"backend", backend == levelset::Backend::Gpu ? "gpu" : "cpu"},
          {"renderer", renderer},
          {"iterations", stats.iterations},
          {"seconds", seconds},
          {"converged", stats.converged},
          {"inside_voxels", insideVoxels},
          {"active_pages_peak", levelSet->pages().stats().peakActive},
          {"physical_bytes_peak", levelSet->physicalBytesPeak()},
          {"half_resolution_iterations", halfResolution.iterations},
          {"half_resolution_seconds", halfResolution.seconds},
          {"topology", topology == levelset::Topology::Preserve ? "preserve" : "free"},
          {"thread_voxels_filled", threadVoxelsFilled}};
}

}  // namespace isoatlas::pipeline
