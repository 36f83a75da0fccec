// planWeld: a stellar weld of v into its neighbour u, step by step in v's ring laid flat, and whether
// each step is a valid triangulation of the ring's polygon there, by exact predicates (Liu et al.
// 2023: flip only convex diamonds, then remove the vertex). When every step is valid, the weld maps
// the ring's polygon onto itself by a piecewise-linear bijection (old faces -> new fan), so the
// parametrisation stays one-to-one by construction.
//   - the star: every face (v, w_i, w_i+1) turns counter-clockwise;
//   - each flip of a spoke (v, w) has a strictly convex diamond; the flips bring v down to four
//     neighbours (an edge weld; a face weld when it has three) or, on the boundary, to two faces;
//     they are taken from both sides of u, the narrower first, to keep the diamonds convex;
//   - the fan left around u turns counter-clockwise.
#pragma once
#include <cstddef>
#include <span>

#include "multires/stellar_operators.h"
#include "multires/vec2.h"

namespace isoatlas::multires {

struct WeldPlan {
  std::size_t target = 0;         // u's ring index
  std::size_t flips[kMaxDegree];  // ring indices of the spokes flipped, in order
  std::size_t flipCount = 0;
  // The fan left around u: ring indices rim[0 .. rimSize), faces (u, rim[m], rim[m + 1]).
  std::size_t rim[kMaxDegree];
  std::size_t rimSize = 0;
};

// Whether v's star (v at the origin, ring vertex i at plane[i]) turns counter-clockwise throughout
// (the faces (v, w_i, w_i+1): k of them, k - 1 on a boundary).
bool starIsValid(std::span<const Vec2> plane, bool boundary);

// Inputs: the ring laid flat (exponentialMap: v at the origin), whether v is a boundary vertex, and
// u's ring index t (an end of the ring on a boundary). Output: the plan. Returns false when a flip's
// diamond is not strictly convex or a face of the fan is not counter-clockwise (the star is
// checked apart, by starIsValid).
bool planWeld(std::span<const Vec2> plane, bool boundary, std::size_t t, WeldPlan& plan);

}  // namespace isoatlas::multires
