// DenseSampler: the dense surface evaluated at a point of the base mesh (a base triangle and
// barycentric coordinates), through the parametrisation: the dense triangle whose parametric image
// holds the point, interpolated. A dense triangle whose corners lie in two neighbouring base
// triangles is unfolded across their shared edge, so points on base edges are covered too. Where no
// dense triangle holds the point (only near a base vertex, where three or more base triangles meet),
// the nearest image is used, and the base triangle itself where it holds no image at all. A base
// vertex belongs to all its base triangles, so the dense triangles around it are imaged in each. Keeps
// references to both meshes.
#pragma once
#include <array>
#include <vector>

#include "multires/base_mesh.h"

namespace isoatlas::multires {

class DenseSampler {
public:
  DenseSampler(const Mesh& dense, const BaseMesh& base);

  Vec3 position(std::uint32_t triangle, const std::array<double, 3>& bary) const;

private:
  struct Image {
    std::uint32_t denseFace;
    std::array<std::array<double, 2>, 3> uv;  // the corners in the base triangle's (bary1, bary2) frame
  };
  const Mesh& dense_;
  const BaseMesh& base_;
  std::vector<std::vector<Image>> images_;  // per base triangle
};

}  // namespace isoatlas::multires
