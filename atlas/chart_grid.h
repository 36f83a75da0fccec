// ChartGrid: a level of a chart as reconstructLevel makes it, over the chart's points: grid
// squares (square (a, b) at b * (n - 1) + a), each cut into two triangles as squareTriangles cuts
// it, linear in the chart. Where a chart point lies in it and the level's point there; the dense
// vertices' distances from it. Used to place texels (relax_chart.h, snap_texels.h).
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <span>
#include <vector>

#include "atlas/reconstruct.h"
#include "core/vec.h"
#include "multires/vec2.h"

namespace isoatlas::atlas {

// A dense vertex inside a tile: its chart point (in (0, 1)^2) and position.
struct ChartVertex {
  multires::Vec2 chart;
  Vec3 position;
};

class ChartGrid {
public:
  using Vec2 = multires::Vec2;
  ChartGrid(std::uint32_t n, const std::vector<Vec2>& q, const std::vector<Vec3>& p) : n_(n), q_(q), p_(p) {}

  std::uint32_t squares() const { return n_ - 1; }

  // The square holding chart point x, walked to from square `from` across the sides x lies beyond
  // (the squares are convex); the last one reached if the walk goes on too long (rounding).
  std::uint32_t locate(const Vec2& x, std::uint32_t from) const {
    const std::uint32_t s = squares();
    std::uint32_t a = from % s, b = from / s;
    for (std::uint32_t step = 0; step < 4 * n_; ++step) {
      const auto c = corners(a, b);
      if (b > 0 && multires::orient2(c[0], c[1], x) < 0) --b;
      else if (a + 1 < s && multires::orient2(c[1], c[2], x) < 0) ++a;
      else if (b + 1 < s && multires::orient2(c[2], c[3], x) < 0) ++b;
      else if (a > 0 && multires::orient2(c[3], c[0], x) < 0) --a;
      else break;
    }
    return b * s + a;
  }
  std::uint32_t guess(const Vec2& x) const {
    const auto at = [&](double t) { return std::uint32_t(std::clamp(t * squares(), 0.0, squares() - 1.0)); };
    return at(x.y) * squares() + at(x.x);
  }

  // The level's point at chart point x of square `square`: linear over the triangle holding it.
  Vec3 pointAt(const Vec2& x, std::uint32_t square) const {
    const std::uint32_t a = square % squares(), b = square / squares();
    const auto k = texels(a, b);
    const auto halves = squareTriangles(a, b);
    std::array<double, 3> best{};
    std::size_t bestHalf = 0;
    double bestLowest = -1e300;
    for (std::size_t h = 0; h < 2; ++h) {
      const auto& t = halves[h];
      const auto w = multires::barycentric2(x, q_[k[t[0]]], q_[k[t[1]]], q_[k[t[2]]]);
      const double lowest = std::min({w[0], w[1], w[2]});
      if (lowest > bestLowest) bestLowest = lowest, best = w, bestHalf = h;
    }
    multires::clampToTriangle(best);
    const auto& t = halves[bestHalf];
    return p_[k[t[0]]] * best[0] + p_[k[t[1]]] * best[1] + p_[k[t[2]]] * best[2];
  }

  // How far the level's triangles stray from the surface: the largest distance between a point of
  // them (a triangle's centroid, an edge's middle) and the surface at that point's chart point.
  // strayAround: the triangles at texel (i, j) and their edges there (what a move of the texel
  // changes); largestStray: every triangle and edge of the grid.
  using SurfaceAt = std::function<Vec3(const Vec2&)>;
  double strayAround(std::uint32_t i, std::uint32_t j, const SurfaceAt& surfaceAt) const {
    const std::size_t t = std::size_t(j) * n_ + i;
    double largest = 0;
    std::array<std::size_t, 8> edgesDone{};
    std::size_t edges = 0;
    for (std::uint32_t b = j - 1; b <= j; ++b)
      for (std::uint32_t a = i - 1; a <= i; ++a) {
        const auto k = texels(a, b);
        for (const auto& h : squareTriangles(a, b)) {
          const std::size_t u = k[h[0]], v = k[h[1]], w = k[h[2]];
          if (u != t && v != t && w != t) continue;
          largest = std::max(largest, strayOf({u, v, w}, surfaceAt));
          for (const std::size_t other : {u, v, w}) {
            if (other == t || std::find(edgesDone.begin(), edgesDone.begin() + edges, other) != edgesDone.begin() + edges) continue;
            edgesDone[edges++] = other;
            largest = std::max(largest, strayOf({t, other}, surfaceAt));
          }
        }
      }
    return largest;
  }
  double largestStray(const SurfaceAt& surfaceAt) const {
    double largest = 0;
    for (std::uint32_t b = 0; b < n_; ++b)
      for (std::uint32_t a = 0; a < n_; ++a) {
        const std::size_t k = std::size_t(b) * n_ + a;
        if (a + 1 < n_) largest = std::max(largest, strayOf({k, k + 1}, surfaceAt));
        if (b + 1 < n_) largest = std::max(largest, strayOf({k, k + n_}, surfaceAt));
        if (a + 1 == n_ || b + 1 == n_) continue;
        const auto corner = texels(a, b);
        const auto halves = squareTriangles(a, b);
        largest = std::max(largest, strayOf({corner[std::size_t(halves[0][0])], corner[std::size_t(halves[0][2])]}, surfaceAt));  // the diagonal
        for (const auto& h : halves)
          largest = std::max(largest, strayOf({corner[std::size_t(h[0])], corner[std::size_t(h[1])], corner[std::size_t(h[2])]}, surfaceAt));
      }
    return largest;
  }

  // Texel indices of square (a, b)'s corners, counter-clockwise from (a, b), as squareTriangles numbers them.
  std::array<std::size_t, 4> texels(std::uint32_t a, std::uint32_t b) const {
    const std::size_t k = std::size_t(b) * n_ + a;
    return {k, k + 1, k + n_ + 1, k + n_};
  }

private:
  // The distance between the mean of some texels' level points and the surface at the mean of their chart points.
  double strayOf(std::initializer_list<std::size_t> texels, const SurfaceAt& surfaceAt) const {
    Vec2 chart;
    Vec3 onLevel;
    for (const std::size_t k : texels) chart = chart + q_[k], onLevel = onLevel + p_[k];
    const double w = 1.0 / double(texels.size());
    return norm(onLevel * w - surfaceAt(chart * w));
  }
  std::array<Vec2, 4> corners(std::uint32_t a, std::uint32_t b) const {
    const auto k = texels(a, b);
    return {q_[k[0]], q_[k[1]], q_[k[2]], q_[k[3]]};
  }
  std::uint32_t n_;
  const std::vector<Vec2>& q_;
  const std::vector<Vec3>& p_;
};

// The largest distance of `vertices` from grid level `grid` at their chart points (0 for none).
double largestVertexError(const ChartGrid& grid, std::span<const ChartVertex> vertices);

// A tile's dense vertices by the square of `grid` that holds each, kept as texels move (a move of
// texel (i, j) changes only which of the four squares round it holds a vertex there).
class VerticesBySquare {
public:
  VerticesBySquare(const ChartGrid& grid, std::span<const ChartVertex> vertices);
  std::uint32_t squareOf(std::uint32_t vertex) const { return squareOf_[vertex]; }
  // The vertices in the four squares round texel (i, j), into `out`.
  void around(std::uint32_t i, std::uint32_t j, std::vector<std::uint32_t>& out) const;
  // After texel (i, j) moved: `vertices` (around's) lie in `squares`, one each.
  void moved(std::uint32_t i, std::uint32_t j, std::span<const std::uint32_t> vertices, std::span<const std::uint32_t> squares);

private:
  std::array<std::uint32_t, 4> squaresAround(std::uint32_t i, std::uint32_t j) const {
    return {(j - 1) * s_ + i - 1, (j - 1) * s_ + i, j * s_ + i - 1, j * s_ + i};
  }
  std::uint32_t s_;
  std::vector<std::uint32_t> squareOf_;
  std::vector<std::vector<std::uint32_t>> inSquare_;  // per square, the vertices in it
};

}  // namespace isoatlas::atlas
