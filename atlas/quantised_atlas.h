// The atlas as the model file stores it (version 3): each chart's positions as 16-bit codes within
// the chart's own bounding box, and every normal as an octahedral code of two bytes (8 + 8 bits):
// 8 bytes a texel instead of 18. Decoding gives each border point two values (each chart its own
// box), so the decoder copies every shared side from the lower-numbered chart into the other and
// sets every corner to its base vertex: neighbouring charts agree bit for bit again.
//   QuantisedChart  one chart's box (lo, step per axis: position = lo + code * step, in f32) and codes
//   quantiseAtlas   inputs: the atlas (its charts' texels); output: one QuantisedChart per chart
//   dequantiseAtlas inputs: the charts, the base mesh (for the shared sides), the layout; output: the
//                   atlas's positions and normals (details untouched)
//   largestQuantisationError  how far (mm) the charts, decoded, lie from the atlas's own positions
//   decodesTo       whether charts decode to exactly this atlas: a file's codes, as read, are then
//                   written back as they are (quantising a decoded atlas again would move it: its
//                   shared borders hold a neighbour's values, which can widen the chart's box)
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "atlas/atlas.h"
#include "multires/base_mesh.h"

namespace isoatlas::atlas {

struct QuantisedChart {
  std::array<float, 3> lo{}, step{};
  std::vector<std::array<std::uint16_t, 3>> positions;  // N x N, row by row
  std::vector<std::array<std::uint8_t, 2>> normals;     // N x N, octahedral
};

std::array<std::uint8_t, 2> encodeOctahedral(const Vec3& normal);
Vec3 decodeOctahedral(const std::array<std::uint8_t, 2>& code);

std::vector<QuantisedChart> quantiseAtlas(const Atlas& atlas);
void dequantiseAtlas(const std::vector<QuantisedChart>& charts, const multires::BaseMesh& base, Atlas& atlas);
double largestQuantisationError(const Atlas& atlas, const std::vector<QuantisedChart>& charts, const multires::BaseMesh& base);
bool decodesTo(const std::vector<QuantisedChart>& charts, const multires::BaseMesh& base, const Atlas& atlas);

}  // namespace isoatlas::atlas
