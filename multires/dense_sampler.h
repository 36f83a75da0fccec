// DenseSampler: the dense surface evaluated at a point of the base mesh (a base triangle and
// barycentric coordinates), through the parametrisation: the dense triangle whose parametric image
// holds the point, interpolated. A dense triangle whose corners lie in several base triangles is
// imaged, through the one chart that holds its corners (BaseDomain::chartFor), in each of their
// frames (in a base vertex's whole star when the chart is that star), so points on base edges and
// around base vertices are covered too. Where no image holds the point (rounding) the nearest image
// is used, and the base triangle itself where it holds no image at all; a dense triangle no chart
// holds is not imaged. Exact only where the parametrisation does
// not fold (untangleParametrisation). Keeps a reference to the dense mesh and its own copy of the
// base triangles' corners, so the base mesh may change afterwards (pairing splits it).
#pragma once
#include <array>
#include <vector>

#include "multires/base_mesh.h"
#include "multires/vec2.h"

namespace isoatlas::multires {

class DenseSampler {
public:
  DenseSampler(const Mesh& dense, const BaseMesh& base);

  Vec3 position(std::uint32_t triangle, const std::array<double, 3>& bary) const;

private:
  struct Image {
    std::uint32_t denseFace;
    std::array<Vec2, 3> uv;  // the corners in the base triangle's (bary1, bary2) frame
  };
  const Mesh& dense_;
  std::vector<std::array<Vec3, 3>> baseCorners_;  // per base triangle, for points no image holds
  std::vector<std::vector<Image>> images_;        // per base triangle
};

}  // namespace isoatlas::multires
