// One polygon split into triangles that cover it once, each turning as the polygon does.
// A fan round one corner does that only where the corner sees the whole polygon: round any other it
// lays triangles of no area (three corners on a line: a CAD polygon with a vertex in the middle of a
// straight side) or turned over (round a convex corner of an L-shaped polygon, as in corner_poly.off
// and mpi.off), and the model built on them folds. So:
//   - a fan round the first corner whose fan has every triangle turning as the polygon, none of no
//     area (the first corner for a convex polygon: most files' polygons split as before);
//   - where that fan has a sliver (a triangle under a millionth of the polygon's area: a corner a
//     file's rounding leaves a hair off a straight side, two of mpi.off's polygons), or no corner
//     sees the whole polygon (a comb, 11 of mpi.off's), the split whose smallest triangle is largest,
//     over the diagonals inside the polygon (up to 64 corners; cubic in them);
//   - past 64 corners, ear clipping in the polygon's plane, the best shaped ear first: an ear is a
//     corner turning as the polygon whose triangle holds no other corner;
//   - a polygon that meets itself at a vertex (a corner listed twice: two loops joined there, or a
//     spike out and back along a side) is first split there into its loops, each split alone; a
//     loop of two corners (the spike) has no area and gives no triangle;
//   - a polygon with no ear (it crosses itself, or has no area): the fan whose smallest triangle is
//     largest.
// "Turning as the polygon" is along the polygon's Newell normal (its vector area), so a polygon a
// little off its plane splits as its projection does.
//   positions  the mesh's vertex positions
//   corners    the polygon's vertices, in order (fewer than 3: no triangle)
// Returns corners.size() - 2 triangles (fewer for a polygon that meets itself: 2 fewer for each
// vertex it meets again), as indices into positions, in the polygon's orientation.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/vec.h"

namespace isoatlas {

std::vector<std::array<std::uint32_t, 3>> triangulatePolygon(std::span<const Vec3> positions,
                                                              std::span<const std::uint32_t> corners);

// The polygon's Newell normal: twice its vector area (its area times its unit normal, exact for a
// plane polygon, convex or not); zero for fewer than 3 corners.
Vec3 newellNormal(std::span<const Vec3> positions, std::span<const std::uint32_t> corners);

}  // namespace isoatlas
