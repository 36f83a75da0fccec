// Pictures of an atlas a person can read: positions as colours (each axis scaled over the charts'
// bounding box to 0..255 in red, green, blue) and normals as colours ((n + 1) / 2 per axis), one
// pixel per texel, black where no chart lies; and where texel quads face backwards
// (backfacing_quads.h): the corners of each such quad red over the normals at a third of their
// brightness.
#pragma once
#include "atlas/atlas.h"
#include "core/image.h"

namespace isoatlas::atlas {

Image positionPreview(const Atlas& atlas);
Image normalPreview(const Atlas& atlas);
Image backFacingPreview(const Atlas& atlas);

}  // namespace isoatlas::atlas
