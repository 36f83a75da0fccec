// BaseDomain: the base mesh as a parameter domain where dense triangles are drawn straight (to count
// those that fold: folded_dense_triangles.h). A point of the domain is a
// base triangle and barycentric weights in it (the triangle's frame). Points move between frames:
// across a shared edge by the unfold (the other triangle's apex mirrored through the edge midpoint,
// an affine map both sides agree on, as if both were equilateral), around a shared vertex through
// that vertex's star laid flat (k equilateral triangles with their angles scaled to a full turn, a
// half turn on the boundary), which spreads the vertex's cone angle evenly instead of piling it on
// one edge. With six triangles around the vertex the two agree. Keeps a reference to the base mesh.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "multires/base_mesh.h"
#include "multires/vec2.h"

namespace isoatlas::multires {

class BaseDomain {
public:
  using Bary = std::array<double, 3>;
  static constexpr std::uint32_t kNone = BaseMesh::kNoTriangle;
  using Point2 = Vec2;
  // A flat chart of part of the domain: a base triangle's frame with its neighbours unfolded into
  // it (vertex == kNone; chart point = weights 1 and 2), or a base vertex's star laid flat (the
  // vertex at the origin, its triangles counter-clockwise, each spanning `step` radians).
  struct Chart {
    std::uint32_t home = kNone, vertex = kNone;
    std::vector<std::uint32_t> star;
    double step = 0;
    bool closed = false;
  };

  explicit BaseDomain(const BaseMesh& base);

  // A dense triangle (three dense vertex indices) in the one chart that holds its corners (chartFor,
  // homed at the first corner's base triangle): the chart and the corners' points in it. False when
  // the corners share no chart.
  bool chartDenseTriangle(std::span<const std::uint32_t> corners, Chart& chart, std::array<Point2, 3>& points) const;

private:
  // Point `bary` of triangle `from` in the frame of `to` (weights may then be negative). Works when
  // the two are the same, share an edge or share a vertex; returns false otherwise.
  bool transfer(std::uint32_t from, const Bary& bary, std::uint32_t to, Bary& out) const;
  // One chart for points of the n given triangles and `home`, so that a dense triangle keeps its
  // shape: home's frame when they lie in home and at most one other triangle, else the star of the
  // base vertex they all share (the unfolds around a vertex do not close up unless it has six
  // triangles). A point on a base vertex or edge counts as in every triangle that holds it. False
  // when they share no vertex.
  bool chartFor(const std::uint32_t* triangles, const Bary* bary, std::size_t n, std::uint32_t home, Chart& chart) const;
  bool toChart(const Chart& chart, std::uint32_t t, const Bary& bary, Point2& out) const;
  // Weights of chart point p in triangle t's frame (any sign); t must lie in the chart.
  bool inFrame(const Chart& chart, const Point2& p, std::uint32_t t, Bary& out) const;
  // The unfold of a point of `from` into neighbour `to` across their shared edge.
  bool unfold(std::uint32_t from, const Bary& bary, std::uint32_t to, Bary& out) const;
  void starChart(std::uint32_t vertex, std::uint32_t someTriangle, Chart& chart) const;
  // Point (t, bary) in the frame of u, where u holds it (u is t, or the point lies on a vertex or an
  // edge u shares with t); false where u does not hold it.
  bool inTriangle(std::uint32_t t, const Bary& bary, std::uint32_t u, Bary& out) const;
  // A triangle around `vertex` that holds point (t, bary) (t itself, or one that holds the corners
  // with weight, for a point on a base vertex or edge), and the point's weights there.
  bool inStar(std::uint32_t vertex, std::uint32_t t, const Bary& bary, std::uint32_t& into, Bary& out) const;

  const BaseMesh& base_;
  std::vector<std::array<std::uint32_t, 3>> across_;
  Rows stars_;  // per base vertex, its triangles
};

}  // namespace isoatlas::multires
