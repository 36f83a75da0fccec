// Pictures of an atlas a person can read: positions as colours (each axis scaled over the charts'
// bounding box to 0..255 in red, green, blue) and normals as colours ((n + 1) / 2 per axis), one
// pixel per texel, black where no chart lies; and where texel quads turn (backfacing_quads.h), over
// the normals at a third of their brightness: the corners of each folded quad red, and yellow those
// of each quad facing against the shading normals only (it lies as its dense face does). An atlas
// without triangleFaceNormals (read from a model file) shows every quad facing against its normals red.
#pragma once
#include "atlas/atlas.h"
#include "core/image.h"

namespace isoatlas::atlas {

Image positionPreview(const Atlas& atlas);
Image normalPreview(const Atlas& atlas);
Image backFacingPreview(const Atlas& atlas);

}  // namespace isoatlas::atlas
