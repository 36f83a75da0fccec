#include "atlas/unturn_texels.h"

#include <algorithm>
#include <cmath>

#include "atlas/reconstruct.h"

namespace isoatlas::atlas {
namespace {

using multires::Vec2;

bool same(const Vec2& a, const Vec2& b) { return a.x == b.x && a.y == b.y; }

// The pass of unturnTexels over one chart.
class Unturner {
public:
  Unturner(std::uint32_t n, std::span<const ChartVertex> vertices, const std::function<SurfacePoint(const Vec2&)>& surfaceAt,
           std::vector<Vec2>& q, std::vector<Vec3>& p, bool keepDiagonal)
      : n_(n), s_(n - 1), keepDiagonal_(keepDiagonal), vertices_(vertices), surfaceAt_(surfaceAt), q_(q), p_(p), level_(n, q, p), bySquare_(level_, vertices) {}

  std::uint32_t run() {
    constexpr int kSweeps = 3;
    std::uint32_t moved = 0;
    for (int sweep = 0; sweep < kSweeps; ++sweep) {
      std::uint32_t movedNow = 0;
      for (std::uint32_t j = 1; j + 1 < n_; ++j)
        for (std::uint32_t i = 1; i + 1 < n_; ++i)
          if (!(keepDiagonal_ && i == j) && turnedAround(i, j) > 0) movedNow += tryPlaces(i, j);
      moved += movedNow;
      if (movedNow == 0) break;
    }
    return moved;
  }

private:
  // The triangles of the four squares round texel (i, j) that fold (countFoldedQuads' test).
  int turnedAround(std::uint32_t i, std::uint32_t j) const {
    int turned = 0;
    for (std::uint32_t b = j - 1; b <= j; ++b)
      for (std::uint32_t a = i - 1; a <= i; ++a) {
        const auto k = level_.texels(a, b);
        for (const auto& t : squareTriangles(a, b)) {
          const std::size_t u = k[std::size_t(t[0])], v = k[std::size_t(t[1])], w = k[std::size_t(t[2])];
          const Vec3 facing = surfaceAt_((q_[u] + q_[v] + q_[w]) * (1.0 / 3)).normal;  // under its centroid
          turned += dot(cross(p_[v] - p_[u], p_[w] - p_[u]), facing) < 0;
        }
      }
    return turned;
  }

  // The four squares' error with texel (i, j) where it is now; `squareAfter` gets where each of their
  // dense vertices (around_) lies.
  double errorAround(std::uint32_t i, std::uint32_t j, std::vector<std::uint32_t>& squareAfter) const {
    double error = level_.strayAround(i, j, [&](const Vec2& x) { return surfaceAt_(x).position; });
    squareAfter.resize(around_.size());
    for (std::size_t m = 0; m < around_.size(); ++m) {
      const ChartVertex& v = vertices_[around_[m]];
      squareAfter[m] = level_.locate(v.chart, bySquare_.squareOf(around_[m]));
      error = std::max(error, norm(v.position - level_.pointAt(v.chart, squareAfter[m])));
    }
    return error;
  }

  // The places texel (i, j) tries, nearest its neighbours' middle first.
  std::vector<Vec2> places(std::uint32_t i, std::uint32_t j) const {
    const std::size_t k = std::size_t(j) * n_ + i;
    const Vec2 middle = (q_[k - 1] + q_[k + 1] + q_[k - n_] + q_[k + n_]) * 0.25;
    std::vector<Vec2> out{middle, {double(i) / s_, double(j) / s_}};
    double lo[2] = {1, 1}, hi[2] = {0, 0};
    for (const std::size_t m : {k - 1, k + 1, k - n_, k + n_}) {
      lo[0] = std::min(lo[0], q_[m].x), hi[0] = std::max(hi[0], q_[m].x);
      lo[1] = std::min(lo[1], q_[m].y), hi[1] = std::max(hi[1], q_[m].y);
    }
    for (int a = -2; a <= 2; ++a)
      for (int b = -2; b <= 2; ++b)
        if (a != 0 || b != 0) out.push_back(middle + Vec2{(hi[0] - lo[0]) * a / 8.0, (hi[1] - lo[1]) * b / 8.0});
    return out;
  }

  // Texel (i, j) moved to its best place, if one turns fewer triangles within the error allowed.
  bool tryPlaces(std::uint32_t i, std::uint32_t j) {
    const std::size_t k = std::size_t(j) * n_ + i;
    bySquare_.around(i, j, around_);
    const int turnedBefore = turnedAround(i, j);
    const double allowed = errorAround(i, j, squareAfter_);
    const Vec2 fromChart = q_[k];
    const Vec3 fromPosition = p_[k];
    int bestTurned = turnedBefore;
    double bestError = 0;
    Vec2 best = fromChart;
    Vec3 bestPosition = fromPosition;
    for (const Vec2& x : places(i, j)) {
      q_[k] = x;
      if (convexAroundTexel(q_, n_, i, j) != 0xF) continue;
      const Vec3 s = surfaceAt_(x).position;
      p_[k] = s;
      const int turned = turnedAround(i, j);
      if (turned > bestTurned) continue;
      const double error = errorAround(i, j, squareAfter_);
      if (error > allowed || (turned == bestTurned && (same(best, fromChart) || error >= bestError))) continue;
      bestTurned = turned, bestError = error, best = x, bestPosition = s;
    }
    q_[k] = best, p_[k] = bestPosition;
    if (same(best, fromChart)) return false;
    errorAround(i, j, squareAfter_);
    bySquare_.moved(i, j, around_, squareAfter_);
    return true;
  }

  std::uint32_t n_, s_;
  bool keepDiagonal_;
  std::span<const ChartVertex> vertices_;
  const std::function<SurfacePoint(const Vec2&)>& surfaceAt_;
  std::vector<Vec2>& q_;
  std::vector<Vec3>& p_;
  ChartGrid level_;
  VerticesBySquare bySquare_;
  std::vector<std::uint32_t> around_, squareAfter_;
};

}  // namespace

std::uint32_t unturnTexels(std::uint32_t n, std::span<const ChartVertex> vertices,
                           const std::function<SurfacePoint(const Vec2&)>& surfaceAt, std::vector<Vec2>& q, std::vector<Vec3>& p,
                           bool keepDiagonal) {
  if (n < 3) return 0;
  return Unturner(n, vertices, surfaceAt, q, p, keepDiagonal).run();
}

}  // namespace isoatlas::atlas
