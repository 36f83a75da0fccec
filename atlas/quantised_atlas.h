// The atlas as the model file stores it (version 4): each chart's positions as 12-bit codes within
// the chart's own bounding box (rounded: at most an 8190th of the box from the atlas's own along
// each axis; a texel whose rounding would fold a triangle round it then moved up to two steps from
// its rounded code, unfold_codes.h, and one that would join another texel up to four more, a side's
// code moving with both its copies, separate_codes.h; bench/RESULTS.md compares the error with
// level 10's largest distance), and every normal as an octahedral code of two bytes (8 + 8 bits).
// Decoding gives each border point two values (each chart its own box), so the decoder copies every
// shared side from the lower-numbered chart into the other and sets every corner to its base
// vertex: neighbouring charts agree bit for bit again. Version 3 files held 16-bit codes; the
// decoder takes codes of any width up to 16 bits (position = lo + code * step).
//   QuantisedChart  one chart's box (lo, step per axis: position = lo + code * step, in f32) and codes
//   quantiseAtlas   inputs: the atlas (its charts' texels) and its base mesh; output: one QuantisedChart
//                   per chart, where rounding folds as few texel triangles as nudging codes can
//                   (unfold_codes.h) and texels the atlas holds apart decode apart (separate_codes.h;
//                   `separated`, when given, gets how many moved for that; `decoded`, the charts'
//                   decode, which the two keep as they move codes)
//   dequantiseAtlas inputs: the charts, the base mesh (for the shared sides), the layout; output: the
//                   atlas's positions and normals (details untouched)
//   largestQuantisationError  how far (mm) the charts' decode lies from the atlas's own positions
//   decodesTo       whether charts decode to exactly this atlas: a file's codes, as read, are then
//                   written back as they are (quantising a decoded atlas again would move it: its
//                   shared borders hold a neighbour's values, which can widen the chart's box)
//   packChartCodes / unpackChartCodes  a chart's codes as the file holds them (version 4): each
//                   channel predicted from its texel's left, upper and upper-left neighbours (the
//                   parallelogram rule, modulo the code's width), the residuals zigzagged and laid
//                   out in byte planes, deflated (zlib). unpack returns false for bytes that do not
//                   inflate to exactly n x n texels' codes.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "atlas/atlas.h"
#include "multires/base_mesh.h"

namespace isoatlas::atlas {

// 12 bits: over the corpus level 10's median is as with 14 (it fell only where the model was
// within float precision of a polyhedron, and by up to 1.1 dB in three cases), the files are a fifth
// smaller, and fewer texel quads fold, since a coarser code grid gives unfoldRoundedTexels more room
// (bench/RESULTS.md, "Position codes").
inline constexpr int kPositionBits = 12;
inline constexpr std::uint16_t kLargestPositionCode = (1u << kPositionBits) - 1;  // 4095

struct QuantisedChart {
  std::array<float, 3> lo{}, step{};
  std::vector<std::array<std::uint16_t, 3>> positions;  // N x N, row by row
  std::vector<std::array<std::uint8_t, 2>> normals;     // N x N, octahedral
};

std::array<std::uint8_t, 2> encodeOctahedral(const Vec3& normal);
Vec3 decodeOctahedral(const std::array<std::uint8_t, 2>& code);

struct SeparatedTexels;
// The position chart q's code stands for: lo + code * step per axis, in floats (what the decoder writes).
inline std::array<float, 3> decodePosition(const QuantisedChart& q, const std::array<std::uint16_t, 3>& code) {
  return {q.lo[0] + float(code[0]) * q.step[0], q.lo[1] + float(code[1]) * q.step[1], q.lo[2] + float(code[2]) * q.step[2]};
}

std::vector<QuantisedChart> quantiseAtlas(const Atlas& atlas, const multires::BaseMesh& base, SeparatedTexels* separated = nullptr,
                                          Atlas* decoded = nullptr);
void dequantiseAtlas(const std::vector<QuantisedChart>& charts, const multires::BaseMesh& base, Atlas& atlas);
double largestQuantisationError(const Atlas& atlas, const Atlas& decoded);
bool decodesTo(const std::vector<QuantisedChart>& charts, const multires::BaseMesh& base, const Atlas& atlas);

std::vector<std::uint8_t> packChartCodes(const QuantisedChart& chart, std::uint32_t n);
bool unpackChartCodes(const std::uint8_t* bytes, std::size_t size, std::uint32_t n, QuantisedChart& chart);

}  // namespace isoatlas::atlas
