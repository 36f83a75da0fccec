// separateJoinedTexels: codes nudged so that quantising never joins texels. A chart's texels can lie
// closer than its code step where the parametrisation squeezes them (a sliver of the dense mesh, a
// hard shear); rounded to the same code, two texels decode to one point, and every level that takes
// both has an edge of length 0 (the capture, welded by position, is then not a manifold: bunny, cow,
// femur and 8 more of the corpus at level 10 before this).
// Every texel whose decoded position (dequantiseAtlas, shared borders and corners included) equals an
// earlier texel's while the atlas holds them apart gets the nearest free code round its own, up to
// four steps along any axes. An inner texel moves first, its code being its own; where
// both are on borders, a side texel's code moves in the chart its copies decode from (the
// lower-numbered one), both copies with it; corners stay (each is its base vertex). Texels the atlas
// holds at the same place (shared samples, or the coincident texels makeAtlas counts) stay together.
//   atlas    the positions the codes stand for
//   base     its base mesh (which tile lies across each side)
//   charts   quantiseAtlas's codes; changed in place
//   decoded  the charts as dequantiseAtlas decodes them; kept so as codes move
// Returns how many inner texels and side codes moved, and how many pairs stayed joined (two corners,
// or no free code within four steps).
#pragma once
#include <cstdint>
#include <vector>

#include "atlas/quantised_atlas.h"

namespace isoatlas::atlas {

struct SeparatedTexels {
  std::uint64_t moved = 0, movedOnSides = 0, joined = 0;
};

SeparatedTexels separateJoinedTexels(const Atlas& atlas, const multires::BaseMesh& base, std::vector<QuantisedChart>& charts,
                                     Atlas& decoded);

}  // namespace isoatlas::atlas
