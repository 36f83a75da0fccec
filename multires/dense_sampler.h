// DenseSampler: the dense surface evaluated at a point of the base mesh (a base triangle and
// barycentric coordinates), through the parametrisation: the dense triangle whose parametric image
// holds the point, interpolated. A dense triangle whose corners lie in several base triangles is
// imaged, through the one chart that holds its corners (BaseDomain::chartFor), in each of their
// frames (in a base vertex's whole star when the chart is that star), so points on base edges and
// around base vertices are covered too; one whose corners share no chart (a long triangle) is
// imaged in each corner's frame through BaseDomain::transferNear. A point no image of its own
// triangle holds (a gap: a triangle's images need not tile it up to its edges) is looked for in the
// neighbours across its edges; where none holds it the nearest image answers, and the base
// triangle itself where it holds no image at all. Folded images (turned over in their frame) are
// never taken: a point one of them holds is answered by the unfolded image that holds it or lies
// nearest, and said to be folded. Exact only where the parametrisation does not fold
// (untangleParametrisation). Keeps a reference to the dense mesh and its own copy of the base
// triangles, so the base mesh may change afterwards (pairing splits it).
// A query looks only at the images listed in its cell of a uniform grid over its base triangle's
// images (about two cells per image), and scans them all only when none of those holds the point: the
// answer is the scan's, bit for bit (`indexed` false scans always: the oracle in tests).
#pragma once
#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "multires/base_domain.h"
#include "multires/base_mesh.h"
#include "multires/vec2.h"

namespace isoatlas::multires {

class DenseSampler {
public:
  DenseSampler(const Mesh& dense, const BaseMesh& base, bool indexed = true);

  // Where the point lands on the dense surface: a dense face and weights of its corners (face is
  // kNoFace when the base triangle holds no unfolded image: then the weights are the base
  // triangle's own, `bary`), whether that image holds the point (else it is only the nearest, the
  // point lying in a gap between images) and whether a folded image holds it.
  static constexpr std::uint32_t kNoFace = ~0u;
  struct Hit {
    std::uint32_t face = kNoFace;
    std::array<double, 3> bary{};
    bool held = false, folded = false;
  };
  Hit locate(std::uint32_t triangle, const std::array<double, 3>& bary) const;
  Vec3 position(std::uint32_t triangle, const std::array<double, 3>& bary) const;
  // The position of a hit (the base triangle's point when it has no face).
  Vec3 hitPosition(std::uint32_t triangle, const Hit& hit) const;

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
  // The image of `triangle` holding `point` (in its frame), else the nearest.
  TriangleHit findImage(std::uint32_t triangle, const Vec2& point) const;

  const Mesh& dense_;
  BaseMesh ownBase_;  // positions and triangles only (for moving points between frames): domain_'s
  std::unique_ptr<BaseDomain> domain_;
  std::vector<std::array<std::uint32_t, 3>> across_;  // per base triangle and edge
  std::vector<std::array<Vec3, 3>> baseCorners_;  // per base triangle, for points no image holds
  std::vector<std::vector<Image>> images_;        // per base triangle, unfolded
  std::vector<std::vector<Image>> foldedImages_;  // per base triangle
  std::vector<ImageGrid> grids_;                  // per base triangle (empty when not indexed)
  mutable std::atomic<std::uint64_t> queries_{0}, fullScans_{0};
};

}  // namespace isoatlas::multires
