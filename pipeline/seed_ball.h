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
// Throws Error unless the voxel index lies inside the volume.
void requireInside(const Volume& v, const Vec3& index, const std::string& what);

}  // namespace isoatlas::pipeline
