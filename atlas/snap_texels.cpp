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
    const auto halves = halvesOf(a, b);
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
        for (const auto& h : halvesOf(a, b)) {
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

  // Square (a, b)'s two triangles, as corners of texels(a, b) (counter-clockwise: 0 (a, b),
  // 1 (a + 1, b), 2 (a + 1, b + 1), 3 (a, b + 1)).
  static std::array<std::array<int, 3>, 2> halvesOf(std::uint32_t a, std::uint32_t b) {
    if (cutAlongMainDiagonal(a, b)) return {{{0, 1, 2}, {0, 2, 3}}};
    return {{{0, 1, 3}, {1, 2, 3}}};
  }

  // Texel indices of square (a, b)'s corners, counter-clockwise from (a, b).
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

}  // namespace

std::uint32_t snapTexels(std::uint32_t n, std::span<const ChartVertex> vertices, const std::function<Vec3(const Vec2&)>& surfaceAt,
                         std::vector<Vec2>& q, std::vector<Vec3>& p) {
  if (n < 3 || vertices.empty()) return 0;
  const FinestLevel level(n, q, p);
  const std::uint32_t s = level.squares();
  // Errors this small are rounding: nothing to mend.
  const double negligible = 1e-9 * boundingBox(p).diagonal();
  std::vector<std::uint32_t> squareOf(vertices.size());
  std::vector<double> error(vertices.size());
  std::vector<std::vector<std::uint32_t>> inSquare(std::size_t(s) * s);
  using Entry = std::pair<double, std::uint32_t>;
  std::priority_queue<Entry> worst;
  for (std::uint32_t d = 0; d < vertices.size(); ++d) {
    const Vec2& x = vertices[d].chart;
    squareOf[d] = level.locate(x, level.guess(x));
    error[d] = norm(vertices[d].position - level.pointAt(x, squareOf[d]));
    inSquare[squareOf[d]].push_back(d);
    if (error[d] > negligible) worst.push({error[d], d});
  }

  std::vector<std::uint8_t> moved(q.size(), 0), tried(vertices.size(), 0);
  std::vector<std::uint32_t> around, squareAfter;
  std::vector<double> errorAfter;
  std::uint32_t snapped = 0;
  while (!worst.empty()) {
    const auto [e, d] = worst.top();
    worst.pop();
    if (tried[d] || e != error[d]) continue;  // done, or an entry from before its square changed
    tried[d] = 1;
    const Vec2& x = vertices[d].chart;
    const auto corners = level.texels(squareOf[d] % s, squareOf[d] / s);
    std::array<std::size_t, 4> order = corners;
    std::sort(order.begin(), order.end(), [&](std::size_t u, std::size_t v) {
      const Vec2 du = q[u] - x, dv = q[v] - x;
      return du.x * du.x + du.y * du.y < dv.x * dv.x + dv.y * dv.y;
    });
    for (const std::size_t t : order) {
      const std::uint32_t i = std::uint32_t(t % n), j = std::uint32_t(t / n);
      if (moved[t] || i == 0 || j == 0 || i + 1 == n || j + 1 == n || (i % 2 == 0 && j % 2 == 0)) continue;
      // The four squares around texel t and the vertices in them, and their largest error now.
      const std::uint32_t squaresAround[4] = {(j - 1) * s + i - 1, (j - 1) * s + i, j * s + i - 1, j * s + i};
      around.clear();
      double before = 0;
      for (const std::uint32_t sq : squaresAround)
        for (const std::uint32_t v : inSquare[sq]) around.push_back(v), before = std::max(before, error[v]);
      const Vec2 fromChart = q[t];
      const Vec3 fromSurface = p[t];
      q[t] = x;
      if (convexAroundTexel(q, n, i, j) != 0xF) {
        q[t] = fromChart;
        continue;
      }
      p[t] = surfaceAt(x);
      squareAfter.resize(around.size()), errorAfter.resize(around.size());
      double after = 0;
      for (std::size_t m = 0; m < around.size(); ++m) {
        const std::uint32_t v = around[m];
        squareAfter[m] = level.locate(vertices[v].chart, squareOf[v]);
        errorAfter[m] = norm(vertices[v].position - level.pointAt(vertices[v].chart, squareAfter[m]));
        after = std::max(after, errorAfter[m]);
      }
      if (after < before) after = std::max(after, level.strayAround(i, j, surfaceAt));
      if (!(after < before)) {
        q[t] = fromChart, p[t] = fromSurface;
        continue;
      }
      moved[t] = 1, ++snapped;
      for (const std::uint32_t sq : squaresAround) inSquare[sq].clear();
      for (std::size_t m = 0; m < around.size(); ++m) {
        const std::uint32_t v = around[m];
        squareOf[v] = squareAfter[m], error[v] = errorAfter[m];
        inSquare[squareOf[v]].push_back(v);
        if (!tried[v] && error[v] > negligible) worst.push({error[v], v});
      }
      break;
    }
  }
  return snapped;
}

}  // namespace isoatlas::atlas
