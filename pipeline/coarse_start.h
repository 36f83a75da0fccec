// A level set's start from its own solution at half the resolution. The volume is averaged 2 x 2 x 2,
// the seeds halved, and the level set solved there until converged: a quarter of the band, and fronts
// that cross the volume's voxels twice as fast. Its mask, brought back to the volume's grid, is where
// the full-resolution level set starts (LevelSet::setMask), and that one then has only the detail
// left to settle.
#pragma once
#include <functional>
#include <vector>

#include "core/volume.h"
#include "core/volume_source.h"
#include "levelset/level_set.h"
#include "pipeline/seed_ball.h"

namespace isoatlas::pipeline {

// Input: any scalar volume, or a source (read four rows at a time per thread, never whole). Output:
// float32, each voxel the mean of its 2 x 2 x 2 block of the input (fewer at an odd edge), dims rounded
// up; spacing doubled and origin at the block's centre, so its voxels lie where the blocks do.
Volume halfResolution(const VolumeSource& source);
Volume halfResolution(const Volume& volume);

struct CoarseStart {
  Volume mask;  // uint8 on the volume's grid: each voxel its block's value at half resolution
  levelset::RunStats stats;
  bool started = true;  // false: acceptStart refused the start (nothing was run, mask is empty)
};

// Inputs: the volume (or its source); params; seeds (voxel indices of the volume) and seedMask (null, or the volume's grid,
//   > 0 inside: a block starts inside when any of its voxels does); options (backend, page size);
//   run (maxIterations, the stopping rule and progress, for the half-resolution solve).
//   acceptStart (optional): given the half-resolution start (the seeds there, on its grid) before the
//   run; false stops there. Each voxel's 2 x 2 x 2 copy keeps the mask's topology ((6+, 18)), so a
//   topology-preserving solve here hands the full resolution the start's topology.
// Output: the half-resolution solution's mask on the volume's grid, and its run's figures.
CoarseStart solveAtHalfResolution(const VolumeSource& source, const levelset::SpeedParams& params, const std::vector<Ball>& seeds,
                                  const Volume* seedMask, const levelset::LevelSetOptions& options,
                                  const levelset::RunOptions& run, const std::function<bool(const Volume&)>& acceptStart = {});
CoarseStart solveAtHalfResolution(const Volume& volume, const levelset::SpeedParams& params, const std::vector<Ball>& seeds,
                                  const Volume* seedMask, const levelset::LevelSetOptions& options,
                                  const levelset::RunOptions& run, const std::function<bool(const Volume&)>& acceptStart = {});

}  // namespace isoatlas::pipeline
