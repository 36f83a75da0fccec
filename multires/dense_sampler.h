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
// A query looks only at the images listed in its cell of a uniform grid over its base triangle's
// images (about two cells per image), and scans them all only when none of those holds the point: the
// answer is the scan's, bit for bit (`indexed` false scans always: the oracle in tests).
#pragma once
#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

#include "multires/base_mesh.h"
#include "multires/vec2.h"

namespace isoatlas::multires {

class DenseSampler {
public:
  DenseSampler(const Mesh& dense, const BaseMesh& base, bool indexed = true);

  Vec3 position(std::uint32_t triangle, const std::array<double, 3>& bary) const;

  // Queries so far, and those that scanned every image of their base triangle (none of their cell's
  // images held the point: off every image, or no grid).
  std::uint64_t queries() const { return queries_; }
  std::uint64_t fullScans() const { return fullScans_; }

private:
  struct Image {
    std::uint32_t denseFace;
    std::array<Vec2, 3> uv;  // the corners in the base triangle's (bary1, bary2) frame
  };
  // Per base triangle: a grid over the bounding box of its images (in its frame), each cell listing
  // the images whose box meets it, in image order.
  struct ImageGrid {
    Vec2 origin;
    double scale = 0;  // cells per unit
    int cells = 0;     // per side; 0: no grid (scan)
    std::vector<std::uint32_t> start, items;  // cell c lists items[start[c] .. start[c + 1])
    // The cell along one axis (points off the grid fall into its edge cells; NaN into the first).
    int cellOf(double x, double o) const {
      const double c = (x - o) * scale;
      return c >= 1 ? int(std::min(c, double(cells - 1))) : 0;
    }
  };
  static ImageGrid makeGrid(const std::vector<Image>& images);

  const Mesh& dense_;
  std::vector<std::array<Vec3, 3>> baseCorners_;  // per base triangle, for points no image holds
  std::vector<std::vector<Image>> images_;        // per base triangle
  std::vector<ImageGrid> grids_;                  // per base triangle (empty when not indexed)
  mutable std::atomic<std::uint64_t> queries_{0}, fullScans_{0};
};

}  // namespace isoatlas::multires
