#include "pipeline/segmentation.h"

#include <chrono>
#include <optional>

#include "core/error.h"
#include "core/progress.h"
#include "levelset/fill_threads.h"
#include "pipeline/coarse_start.h"
#include "pipeline/mask_topology.h"

namespace isoatlas::pipeline {
namespace {

// The run's options: iterations, the stopping rule, and `progress`'s line (none while it is unset).
levelset::RunOptions runOptionsOf(const SegmentationRequest& request, std::optional<Progress>& progress) {
  return {.maxIterations = request.maxIterations,
          .untilConverged = request.untilConverged,
          .progress = [&progress](int i, std::int64_t) {
            if (progress) progress->update(std::uint64_t(i));
          }};
}

std::string topologyWords(const MaskTopology& t) {
  const auto count = [](std::int64_t n, const char* what) { return std::to_string(n) + " " + what + (n == 1 ? "" : "s"); };
  return count(t.components, "component") + " and " + count(t.surfaces, "surface") + " of Euler number " + std::to_string(t.euler);
}

// The half-resolution start (coarse_start.h) in place of the seeds s.levelSet holds. With the topology
// preserved, the half resolution keeps it too, from seeds of the full resolution's topology: where
// halving changes theirs (it can join two seeds or close a gap), the seeds stay, one line says why,
// and this returns false.
bool startAtHalfResolution(const VolumeSource& source, const SegmentationRequest& request, Segmentation& s) {
  const bool preserve = request.topology == levelset::Topology::Preserve;
  MaskTopology seeds;
  if (preserve) seeds = maskTopology(s.levelSet->mask());
  std::optional<Progress> progress;  // the line only for a run that happens
  const auto sameTopology = [&](const Volume& halfSeeds) {
    const MaskTopology half = preserve ? maskTopology(halfSeeds) : seeds;
    if (half == seeds) {
      progress.emplace(request.label + " at half resolution", std::uint64_t(request.maxIterations), "iterations");
      return true;
    }
    logInfo(request.label + ": --half-resolution-start left out: at half resolution the seeds have " + topologyWords(half) +
            ", at full resolution " + topologyWords(seeds) + ", and --topology preserve keeps the seeds' own");
    return false;
  };
  const CoarseStart coarse = solveAtHalfResolution(source, request.params, request.seeds, request.seedMask,
                                                   {.backend = s.backend, .pageSize = request.pageSize, .topology = request.topology},
                                                   runOptionsOf(request, progress), sameTopology);
  if (progress) progress->finish();
  if (!coarse.started) return false;
  s.halfResolution = coarse.stats;
  s.levelSet->setMask(coarse.mask);
  return true;
}

}  // namespace

Segmentation segmentVolume(const Volume& volume, const SegmentationRequest& request) {
  return segmentVolume(VolumeInMemory::compact(volume), request);
}

Segmentation segmentVolume(std::shared_ptr<const VolumeSource> source, const SegmentationRequest& request) {
  Segmentation s;
  s.backend = request.backend;
  s.renderer = request.renderer;
  s.topology = request.topology;
  s.levelSet = std::make_unique<levelset::LevelSet>(
      source, request.params, levelset::LevelSetOptions{.backend = s.backend, .pageSize = request.pageSize, .topology = request.topology});
  const auto start = std::chrono::steady_clock::now();
  require(!request.halfResolutionStart || request.untilConverged, "the half-resolution start needs the run until converged (--converge)");
  // The seeds: the start, unless the half-resolution one takes their place (it needs them to compare
  // topologies when the topology is preserved).
  if (!request.halfResolutionStart || request.topology == levelset::Topology::Preserve) {
    if (request.seedMask) s.levelSet->setMask(*request.seedMask);
    for (const Ball& b : request.seeds) s.levelSet->addSphere(b.centre, b.radius);
  }
  if (request.halfResolutionStart) s.halfResolutionStarted = startAtHalfResolution(*source, request, s);
  std::optional<Progress> progress;
  progress.emplace(request.label, std::uint64_t(request.maxIterations), "iterations");
  s.stats = s.levelSet->run(runOptionsOf(request, progress));
  progress->finish();
  if (request.topology == levelset::Topology::Preserve) {
    // The threads of background the held voxels leave (fill_threads.h) filled, and the front run on
    // from there (phi is rebuilt from the mask).
    Volume mask = s.levelSet->mask();
    s.threadVoxelsFilled = levelset::fillThreads(mask);
    if (s.threadVoxelsFilled > 0) {
      s.levelSet->setMask(mask);
      progress.emplace(request.label + " (threads filled)", std::uint64_t(request.maxIterations), "iterations");
      const levelset::RunStats more = s.levelSet->run(runOptionsOf(request, progress));
      progress->finish();
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
