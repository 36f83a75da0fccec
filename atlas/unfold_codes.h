// unfoldRoundedTexels: codes nudged so that rounding folds as few of the finest level's triangles as
// it can. A texel triangle smaller than a few code steps (the folds' and slivers' size: bench/RESULTS.md,
// "Folds") can turn over when its corners are rounded to the code grid, and a coarser grid turns
// more. A triangle folds as countFoldedQuads counts it (backfacing_quads.h): it faces against the
// dense face under its centroid, or, in an atlas without those normals (one read from a file),
// against the same triangle of the atlas's float positions.
// Each texel off the chart's border with a folded triangle round it (or one of no area) tries the
// codes one step from its rounded code along any axes, then two: a code is taken when fewer of the
// triangles of its four squares fold (as many, and fewer have no area), the nearest to the atlas's own
// position among those with the fewest; three sweeps, since a move changes its neighbours' triangles too. No code ends more than two
// steps from its rounded one along any axis. Border codes stay: they are shared with the charts across
// (the squares' inner corners move instead). Run before separateJoinedTexels, which then keeps texels
// the atlas holds apart apart.
//   atlas    the positions the codes stand for (and their dense face normals, where it has them)
//   charts   quantiseAtlas's codes; changed in place
//   decoded  the charts as dequantiseAtlas decodes them (shared borders included); kept so as the
//            codes move (only inner codes move, and an inner texel decodes from its own code alone)
// Returns how many texels' codes moved.
#pragma once
#include <cstdint>
#include <vector>

#include "atlas/quantised_atlas.h"

namespace isoatlas::atlas {

std::uint64_t unfoldRoundedTexels(const Atlas& atlas, std::vector<QuantisedChart>& charts, Atlas& decoded);

}  // namespace isoatlas::atlas
