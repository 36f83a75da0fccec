// probeSphere: mean and standard deviation of a volume inside a ball, and the level-set parameters
// they suggest (Lefohn's thesis, sec. 4.2.2: T = mean, eps = standard deviation).
//   centre: voxel index (may be fractional); radius: in voxels
// Throws Error if the centre lies outside the volume or the ball holds no voxel.
#pragma once
#include <cstdint>

#include "core/volume.h"

namespace isoatlas::levelset {

struct ProbeResult {
  double mean = 0, std = 0;
  std::int64_t voxels = 0;
  double suggestedTarget() const { return mean; }
  double suggestedWidth() const { return std; }
};

ProbeResult probeSphere(const Volume& volume, const Vec3& centre, double radius);

}  // namespace isoatlas::levelset
