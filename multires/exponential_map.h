// exponentialMap: lays a vertex's 1-ring flat around it, keeping the distances to the neighbours and
// scaling the angles between them to a full turn (a half turn for a boundary vertex, which then lies
// on the straight line between its boundary neighbours). The local parametrisation of a stellar weld.
#pragma once
#include <cmath>
#include <vector>

#include "multires/stellar_operators.h"

namespace isoatlas::multires {

struct Vec2 {
  double x = 0, y = 0;
  Vec2 operator+(const Vec2& o) const { return {x + o.x, y + o.y}; }
  Vec2 operator-(const Vec2& o) const { return {x - o.x, y - o.y}; }
  Vec2 operator*(double s) const { return {x * s, y * s}; }
};
inline double cross2(const Vec2& a, const Vec2& b) { return a.x * b.y - a.y * b.x; }
// Twice the signed area of (a, b, c): positive when counter-clockwise.
inline double orient2(const Vec2& a, const Vec2& b, const Vec2& c) { return cross2(b - a, c - a); }

// Inputs: the mesh, the vertex v and its oneRing. Output: `plane`, the plane position of each ring
// vertex (v at the origin), in ring order. Returns false when the ring is degenerate (a zero-length
// edge, a zero total angle) or has more than 64 vertices.
bool exponentialMap(const StellarMesh& mesh, VertexH v, const OneRing& ring, std::vector<Vec2>& plane);

// Barycentric coordinates of p in triangle (a, b, c); any sign.
std::array<double, 3> barycentric2(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c);

}  // namespace isoatlas::multires
