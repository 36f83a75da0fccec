// Ball: a seed or a sphere in voxel indices; requireInside checks that a point lies in the volume.
#pragma once
#include <string>

#include "core/vec.h"
#include "core/volume.h"

namespace isoatlas::pipeline {

struct Ball {
  Vec3 centre;
  double radius;
};
// The radii a seed or probe ball may have, in voxels (the command line's, Python's): from half a voxel,
// below which it holds at most one, to a thousand.
inline constexpr double kMinBallRadius = 0.5, kMaxBallRadius = 1000;
// Throws Error unless the voxel index lies inside the volume.
void requireInside(const Volume& v, const Vec3& index, const std::string& what);

}  // namespace isoatlas::pipeline
