#include "atlas/snap_texels.h"

#include <algorithm>
#include <cmath>
#include <queue>

#include "atlas/reconstruct.h"
#include "atlas/relax_chart.h"

namespace isoatlas::atlas {
namespace {

using multires::Vec2;

// The finest level over a chart: its grid squares (square (a, b) at b * (n - 1) + a), each cut
// into two triangles as reconstructLevel cuts it.
class FinestLevel {
public:
  FinestLevel(std::uint32_t n, const std::vector<Vec2>& q, const std::vector<Vec3>& p) : n_(n), q_(q), p_(p) {}

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

  // How far the level's triangles at texel (i, j) stray from the surface: the largest distance
  // between a point of them (their centroids and the middles of their edges at the texel: what a
  // move of the texel changes) and the surface at that point's chart point.
  double strayAround(std::uint32_t i, std::uint32_t j, const std::function<Vec3(const Vec2&)>& surfaceAt) const {
    const std::size_t t = std::size_t(j) * n_ + i;
    auto stray = [&](const Vec2& x, const Vec3& onLevel) { return norm(onLevel - surfaceAt(x)); };
    double largest = 0;
    std::array<std::size_t, 8> edgesDone{};
    std::size_t edges = 0;
    for (std::uint32_t b = j - 1; b <= j; ++b)
      for (std::uint32_t a = i - 1; a <= i; ++a) {
        const auto k = texels(a, b);
        for (const auto& h : squareTriangles(a, b)) {
          const std::size_t u = k[h[0]], v = k[h[1]], w = k[h[2]];
          if (u != t && v != t && w != t) continue;
          largest = std::max(largest, stray((q_[u] + q_[v] + q_[w]) * (1.0 / 3), (p_[u] + p_[v] + p_[w]) * (1.0 / 3)));
          for (const std::size_t other : {u, v, w}) {
            if (other == t || std::find(edgesDone.begin(), edgesDone.begin() + edges, other) != edgesDone.begin() + edges) continue;
            edgesDone[edges++] = other;
            largest = std::max(largest, stray((q_[t] + q_[other]) * 0.5, (p_[t] + p_[other]) * 0.5));
          }
        }
      }
    return largest;
  }

  // Texel indices of square (a, b)'s corners, counter-clockwise from (a, b), as squareTriangles numbers them.
  std::array<std::size_t, 4> texels(std::uint32_t a, std::uint32_t b) const {
    const std::size_t k = std::size_t(b) * n_ + a;
    return {k, k + 1, k + n_ + 1, k + n_};
  }

private:
  std::array<Vec2, 4> corners(std::uint32_t a, std::uint32_t b) const {
    const auto k = texels(a, b);
    return {q_[k[0]], q_[k[1]], q_[k[2]], q_[k[3]]};
  }
  std::uint32_t n_;
  const std::vector<Vec2>& q_;
  const std::vector<Vec3>& p_;
};

// The greedy pass of snapTexels over one chart.
class Snapper {
public:
  Snapper(std::uint32_t n, std::span<const ChartVertex> vertices, const std::function<Vec3(const Vec2&)>& surfaceAt,
          std::vector<Vec2>& q, std::vector<Vec3>& p)
      : n_(n), s_(n - 1), vertices_(vertices), surfaceAt_(surfaceAt), q_(q), p_(p), level_(n, q, p),
        squareOf_(vertices.size()), error_(vertices.size()), inSquare_(std::size_t(s_) * s_), moved_(q.size(), 0),
        tried_(vertices.size(), 0) {
    // Errors this small are rounding: nothing to mend.
    negligible_ = 1e-9 * boundingBox(p).diagonal();
    for (std::uint32_t d = 0; d < vertices.size(); ++d) {
      const Vec2& x = vertices[d].chart;
      squareOf_[d] = level_.locate(x, level_.guess(x));
      error_[d] = norm(vertices[d].position - level_.pointAt(x, squareOf_[d]));
      inSquare_[squareOf_[d]].push_back(d);
      if (error_[d] > negligible_) worst_.push({error_[d], d});
    }
  }

  // Worst vertex first: the nearest movable corner of its square that takes it.
  std::uint32_t run() {
    std::uint32_t snapped = 0;
    while (!worst_.empty()) {
      const auto [e, d] = worst_.top();
      worst_.pop();
      if (tried_[d] || e != error_[d]) continue;  // done, or an entry from before its square changed
      tried_[d] = 1;
      const Vec2& x = vertices_[d].chart;
      std::array<std::size_t, 4> corners = level_.texels(squareOf_[d] % s_, squareOf_[d] / s_);
      std::sort(corners.begin(), corners.end(), [&](std::size_t u, std::size_t v) {
        const Vec2 du = q_[u] - x, dv = q_[v] - x;
        return du.x * du.x + du.y * du.y < dv.x * dv.x + dv.y * dv.y;
      });
      for (const std::size_t t : corners)
        if (movable(t) && tryMove(t, x)) {
          ++snapped;
          break;
        }
    }
    return snapped;
  }

private:
  // A texel of the finest two levels, off the border, not moved yet.
  bool movable(std::size_t t) const {
    const std::uint32_t i = std::uint32_t(t % n_), j = std::uint32_t(t / n_);
    return !moved_[t] && i > 0 && j > 0 && i + 1 < n_ && j + 1 < n_ && (i % 2 == 1 || j % 2 == 1);
  }

  // Texel t moved to chart point `to`, kept only if the squares around it stay strictly convex, the
  // largest error of the vertices in them falls, and the level's triangles at t stray less than it was.
  bool tryMove(std::size_t t, const Vec2& to) {
    const std::uint32_t i = std::uint32_t(t % n_), j = std::uint32_t(t / n_);
    const std::uint32_t squaresAround[4] = {(j - 1) * s_ + i - 1, (j - 1) * s_ + i, j * s_ + i - 1, j * s_ + i};
    around_.clear();
    double before = 0;
    for (const std::uint32_t sq : squaresAround)
      for (const std::uint32_t v : inSquare_[sq]) around_.push_back(v), before = std::max(before, error_[v]);
    const Vec2 fromChart = q_[t];
    const Vec3 fromSurface = p_[t];
    q_[t] = to;
    if (convexAroundTexel(q_, n_, i, j) != 0xF) {
      q_[t] = fromChart;
      return false;
    }
    p_[t] = surfaceAt_(to);
    squareAfter_.resize(around_.size()), errorAfter_.resize(around_.size());
    double after = 0;
    for (std::size_t m = 0; m < around_.size(); ++m) {
      const ChartVertex& v = vertices_[around_[m]];
      squareAfter_[m] = level_.locate(v.chart, squareOf_[around_[m]]);
      errorAfter_[m] = norm(v.position - level_.pointAt(v.chart, squareAfter_[m]));
      after = std::max(after, errorAfter_[m]);
    }
    if (after < before) after = std::max(after, level_.strayAround(i, j, surfaceAt_));
    if (!(after < before)) {
      q_[t] = fromChart, p_[t] = fromSurface;
      return false;
    }
    moved_[t] = 1;
    for (const std::uint32_t sq : squaresAround) inSquare_[sq].clear();
    for (std::size_t m = 0; m < around_.size(); ++m) {
      const std::uint32_t v = around_[m];
      squareOf_[v] = squareAfter_[m], error_[v] = errorAfter_[m];
      inSquare_[squareOf_[v]].push_back(v);
      if (!tried_[v] && error_[v] > negligible_) worst_.push({error_[v], v});
    }
    return true;
  }

  std::uint32_t n_, s_;
  std::span<const ChartVertex> vertices_;
  const std::function<Vec3(const Vec2&)>& surfaceAt_;
  std::vector<Vec2>& q_;
  std::vector<Vec3>& p_;
  FinestLevel level_;
  double negligible_ = 0;
  std::vector<std::uint32_t> squareOf_;
  std::vector<double> error_;
  std::vector<std::vector<std::uint32_t>> inSquare_;  // per square, the vertices in it
  std::vector<std::uint8_t> moved_, tried_;
  std::priority_queue<std::pair<double, std::uint32_t>> worst_;  // (error, vertex), stale entries skipped
  std::vector<std::uint32_t> around_, squareAfter_;
  std::vector<double> errorAfter_;
};

}  // namespace

std::uint32_t snapTexels(std::uint32_t n, std::span<const ChartVertex> vertices, const std::function<Vec3(const Vec2&)>& surfaceAt,
                         std::vector<Vec2>& q, std::vector<Vec3>& p) {
  if (n < 3 || vertices.empty()) return 0;
  return Snapper(n, vertices, surfaceAt, q, p).run();
}

}  // namespace isoatlas::atlas
