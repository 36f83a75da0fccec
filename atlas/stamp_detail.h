// stampDetail: fine detail pressed into the surface (the paper's Fig. 10): a grey image (a picture,
// or a word rendered by core/text.h) laid on the tangent plane at a surface point and displaced
// along the normal, its ink (255) `depth` deep. The image, its aspect kept, fits the disc of `radius`
// around the point (its diagonal is the disc's diameter; image up is the world's +z as seen from
// outside, or +y where the normal is near z); texels farther than `radius` or facing away are left
// alone. Every tile the stamp reaches gets a detail chart of `detailSize` texels (the tile's chart,
// upsampled as the finest level triangulates it, then stamped), and the tiles' own charts are
// stamped too, so coarser levels show it at their resolution. Positions move by p - n depth g(p)
// and normals tilt by the stamp's slope, n + depth grad g, both functions of the texel alone, and
// detail borders are upsampled along each base edge in one direction: shared borders stay identical
// bit for bit, so the surface stays closed. A second stamp on a tile with a detail chart stamps it.
//   base, atlas   the model (atlas changed in place)
// Throws Error(BadInput) for an empty image, a radius that is not finite and positive, a depth that
// is zero or deeper than the radius, a detail size that is not 2^k + 1 above the chart size (at most 129), or one
// other than the detail charts already there.
#pragma once
#include <cstdint>

#include "atlas/atlas.h"
#include "core/image.h"
#include "multires/base_mesh.h"

namespace isoatlas::atlas {

struct Stamp {
  Image image;  // grey or RGB (luminance); bright is ink
  Vec3 at;      // a point at or near the surface: the nearest texel is the stamp's centre
  double radius = 10, depth = 1;  // mm; depth > 0 engraves, < 0 embosses
  std::uint32_t detailSize = 129;
};

struct StampStats {
  Vec3 centre, normal;              // the texel the stamp is centred on
  std::uint32_t detailTiles = 0;    // tiles given (or stamped in) a detail chart
  std::uint64_t texelsChanged = 0;  // in the tiles' own charts
  std::uint64_t detailTexelsChanged = 0;
};

StampStats stampDetail(const multires::BaseMesh& base, Atlas& atlas, const Stamp& stamp);

}  // namespace isoatlas::atlas
