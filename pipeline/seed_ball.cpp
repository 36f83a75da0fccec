#include "pipeline/seed_ball.h"

#include "core/error.h"

namespace isoatlas::pipeline {

void requireInside(const Volume& v, const Vec3& p, const std::string& what) {
  for (int a = 0; a < 3; ++a)
    if (p[a] < 0 || p[a] > double(v.dims[a] - 1))
      throw Error(what + " (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) +
                  ") lies outside the volume, whose voxel indices run 0.." + std::to_string(v.dims[0] - 1) + ", 0.." +
                  std::to_string(v.dims[1] - 1) + ", 0.." + std::to_string(v.dims[2] - 1));
}

}  // namespace isoatlas::pipeline
