#include "pipeline/segmentation.h"

#include <chrono>
#include <optional>

#include "core/error.h"
#include "core/progress.h"
#include "levelset/fill_threads.h"
#include "pipeline/coarse_start.h"
#include "pipeline/mask_topology.h"

namespace isoatlas::pipeline {

Segmentation segmentVolume(const Volume& volume, const SegmentationRequest& request) {
  Segmentation s;
  s.backend = request.backend;
  s.renderer = request.renderer;
  s.topology = request.topology;
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
  const bool preserve = request.topology == levelset::Topology::Preserve;
  // The seeds at full resolution: the start, unless the half-resolution one takes its place. With the
  // topology preserved, that one must start from seeds of the same topology on its own grid (halving
  // can join two seeds or close a gap); else the start stays here, and one line says why.
  const auto seedAtFullResolution = [&] {
    if (request.seedMask) s.levelSet->setMask(*request.seedMask);
    for (const Ball& b : request.seeds) s.levelSet->addSphere(b.centre, b.radius);
  };
  if (!request.halfResolutionStart || preserve) seedAtFullResolution();
  if (request.halfResolutionStart) {
    MaskTopology seeds;
    if (preserve) seeds = maskTopology(s.levelSet->mask());
    // The progress line only for a run that happens.
    std::optional<Progress> progress;
    const auto sameTopology = [&](const Volume& halfSeeds) {
      const bool same = !preserve || maskTopology(halfSeeds) == seeds;
      if (same) progress.emplace(request.label + " at half resolution", std::uint64_t(request.maxIterations), "iterations");
      if (same) return true;
      const MaskTopology half = maskTopology(halfSeeds);
      const auto said = [](const MaskTopology& t) {
        const auto count = [](std::int64_t n, const char* what) { return std::to_string(n) + " " + what + (n == 1 ? "" : "s"); };
        return count(t.components, "component") + " and " + count(t.surfaces, "surface") + " of Euler number " + std::to_string(t.euler);
      };
      logInfo(request.label + ": --half-resolution-start left out: at half resolution the seeds have " + said(half) +
              ", at full resolution " + said(seeds) + ", and --topology preserve keeps the seeds' own");
      return false;
    };
    const levelset::RunOptions halfRun{.maxIterations = request.maxIterations,
                                       .untilConverged = request.untilConverged,
                                       .progress = [&progress](int i, std::int64_t) {
                                         if (progress) progress->update(std::uint64_t(i));
                                       }};
    CoarseStart coarse = solveAtHalfResolution(volume, request.params, request.seeds, request.seedMask,
                                               {.backend = s.backend, .pageSize = request.pageSize, .topology = request.topology},
                                               halfRun, sameTopology);
    if (progress) progress->finish();
    s.halfResolutionStarted = coarse.started;
    if (coarse.started) {
      s.halfResolution = coarse.stats;
      s.levelSet->setMask(coarse.mask);
    }
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
          {"half_resolution_started", halfResolutionStarted},
          {"topology", topology == levelset::Topology::Preserve ? "preserve" : "free"},
          {"thread_voxels_filled", threadVoxelsFilled}};
}

}  // namespace isoatlas::pipeline
