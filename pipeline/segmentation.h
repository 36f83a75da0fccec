// The segmentation `segment` and `run` share: a level set on the chosen backend (its GL context current
// when it is the GPU), seeded by balls (and a mask), or when asked through its solution at half the
// resolution (pipeline/coarse_start.h), run with progress on stderr, the mask read back
// once (and phi, when asked for: the mask is then made from it).
#pragma once
#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

#include "pipeline/gpu.h"
#include "pipeline/seed_ball.h"
#include "levelset/level_set.h"

namespace isoatlas::pipeline {

// The defaults `segment`, `run`, Python and the cohort share for a volume of the user's (the demo volume
// has its own tuned ones, pipeline/demo.h): the intensity term's weight against curvature, and a seed
// ball's radius in voxels when --seed gives none.
inline constexpr double kDefaultAlpha = 0.5;
inline constexpr double kDefaultSeedRadius = 3;

struct SegmentationRequest {
  levelset::SpeedParams params;
  std::vector<Ball> seeds;
  const Volume* seedMask = nullptr;  // same grid as the volume; voxels > 0 start inside
  levelset::Backend backend = levelset::Backend::Cpu;  // chooseBackend's
  std::string renderer = "cpu";
  int pageSize = levelset::LevelSetOptions{}.pageSize;
  int maxIterations = levelset::RunOptions{}.maxIterations;
  bool untilConverged = levelset::RunOptions{}.untilConverged;
  std::string label = "segment";  // the progress line's name
  bool readPhi = false;           // read phi back whole (for a phi file)
  // Start from the solution at half the resolution (pipeline/coarse_start.h) instead of the seeds;
  // only with untilConverged (a count of steps from the seeds means what it says; Error otherwise).
  // With topology Preserve it is solved with the topology preserved too, from seeds of the full
  // resolution's topology (pipeline/mask_topology.h); where halving changes that, the start is the
  // full resolution's seeds (halfResolutionStarted false, one line saying why).
  bool halfResolutionStart = false;
  levelset::Topology topology = levelset::Topology::Free;  // Preserve: the seeds' topology kept
};

struct Segmentation {
  std::unique_ptr<levelset::LevelSet> levelSet;  // kept for extraction over its active pages
  levelset::Backend backend = levelset::Backend::Cpu;
  std::string renderer;
  levelset::RunStats stats;            // the full-resolution run
  levelset::RunStats halfResolution;   // the start's run, when there was one (else 0 iterations)
  bool halfResolutionStarted = false;  // the start was the half resolution's solution
  levelset::Topology topology = levelset::Topology::Free;
  std::int64_t threadVoxelsFilled = 0;  // preserved: levelset/fill_threads.h's, before the front ran on
  int iterationsAfterFill = 0;          // of stats.iterations, those after the filling
  double seconds = 0;                  // the whole segmentation, start included
  Volume phi, mask;  // phi: empty unless asked for
  std::int64_t insideVoxels = 0;
  // backend, renderer, iterations, seconds, converged, inside_voxels, active_pages_peak,
  // physical_bytes_peak, half_resolution_iterations, half_resolution_seconds, half_resolution_started,
  // topology, thread_voxels_filled
  nlohmann::json figures() const;
};

// The volume as a source (core/volume_source.h: read page by page as the band reaches it, such as a
// mapped file), or a Volume, held compactly as a source.
Segmentation segmentVolume(std::shared_ptr<const VolumeSource> source, const SegmentationRequest& request);
Segmentation segmentVolume(const Volume& volume, const SegmentationRequest& request);

}  // namespace isoatlas::pipeline
