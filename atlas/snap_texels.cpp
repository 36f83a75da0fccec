#include "atlas/snap_texels.h"

#include <algorithm>
#include <cmath>
#include <queue>

#include "atlas/chart_grid.h"
#include "atlas/reconstruct.h"
#include "atlas/relax_chart.h"

namespace isoatlas::atlas {
namespace {

using multires::Vec2;

// The greedy pass of snapTexels over one chart.
class Snapper {
public:
  Snapper(std::uint32_t n, std::span<const ChartVertex> vertices, const std::function<Vec3(const Vec2&)>& surfaceAt,
          std::vector<Vec2>& q, std::vector<Vec3>& p, bool keepDiagonal)
      : n_(n), s_(n - 1), keepDiagonal_(keepDiagonal), vertices_(vertices), surfaceAt_(surfaceAt), q_(q), p_(p), level_(n, q, p),
        bySquare_(level_, vertices), error_(vertices.size()), moved_(q.size(), 0), tried_(vertices.size(), 0) {
    // Errors this small are rounding: nothing to mend.
    negligible_ = 1e-9 * boundingBox(p).diagonal();
    for (std::uint32_t d = 0; d < vertices.size(); ++d) {
      error_[d] = norm(vertices[d].position - level_.pointAt(vertices[d].chart, bySquare_.squareOf(d)));
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
      std::array<std::size_t, 4> corners = level_.texels(bySquare_.squareOf(d) % s_, bySquare_.squareOf(d) / s_);
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
    return !moved_[t] && i > 0 && j > 0 && i + 1 < n_ && j + 1 < n_ && (i % 2 == 1 || j % 2 == 1) && !(keepDiagonal_ && i == j);
  }

  // Texel t moved to chart point `to`, kept only if the squares around it stay strictly convex, the
  // largest error of the vertices in them falls, and the level's triangles at t stray less than it was.
  bool tryMove(std::size_t t, const Vec2& to) {
    const std::uint32_t i = std::uint32_t(t % n_), j = std::uint32_t(t / n_);
    bySquare_.around(i, j, around_);
    double before = 0;
    for (const std::uint32_t v : around_) before = std::max(before, error_[v]);
    const Vec2 fromChart = q_[t];
    const Vec3 fromSurface = p_[t];
    q_[t] = to;
    if (convexAroundTexel(q_, n_, i, j) != 0xF) {
      q_[t] = fromChart;
      return false;
    }
    p_[t] = surfaceAt_(to);
    if (joinsANeighbour(i, j)) {
      q_[t] = fromChart, p_[t] = fromSurface;
      return false;
    }
    squareAfter_.resize(around_.size()), errorAfter_.resize(around_.size());
    double after = 0;
    for (std::size_t m = 0; m < around_.size(); ++m) {
      const ChartVertex& v = vertices_[around_[m]];
      squareAfter_[m] = level_.locate(v.chart, bySquare_.squareOf(around_[m]));
      errorAfter_[m] = norm(v.position - level_.pointAt(v.chart, squareAfter_[m]));
      after = std::max(after, errorAfter_[m]);
    }
    if (after < before) after = std::max(after, level_.strayAround(i, j, surfaceAt_));
    if (!(after < before)) {
      q_[t] = fromChart, p_[t] = fromSurface;
      return false;
    }
    moved_[t] = 1;
    bySquare_.moved(i, j, around_, squareAfter_);
    for (std::size_t m = 0; m < around_.size(); ++m) {
      const std::uint32_t v = around_[m];
      error_[v] = errorAfter_[m];
      if (!tried_[v] && error_[v] > negligible_) worst_.push({error_[v], v});
    }
    return true;
  }

  // Whether texel (i, j) lies where one of its eight neighbours does, as the atlas stores them
  // (floats): a dense vertex within rounding of the tile's border is where the border sample beside
  // it already is (anchor_dense: chart points 2e-8 apart), and the two would be one vertex.
  bool joinsANeighbour(std::uint32_t i, std::uint32_t j) const {
    auto stored = [](const Vec3& x) { return std::array<float, 3>{float(x.x), float(x.y), float(x.z)}; };
    const auto here = stored(p_[std::size_t(j) * n_ + i]);
    for (std::uint32_t b = j - 1; b <= j + 1; ++b)
      for (std::uint32_t a = i - 1; a <= i + 1; ++a)
        if ((a != i || b != j) && stored(p_[std::size_t(b) * n_ + a]) == here) return true;
    return false;
  }

  std::uint32_t n_, s_;
  bool keepDiagonal_;
  std::span<const ChartVertex> vertices_;
  const std::function<Vec3(const Vec2&)>& surfaceAt_;
  std::vector<Vec2>& q_;
  std::vector<Vec3>& p_;
  ChartGrid level_;
  double negligible_ = 0;
  VerticesBySquare bySquare_;
  std::vector<double> error_;
  std::vector<std::uint8_t> moved_, tried_;
  std::priority_queue<std::pair<double, std::uint32_t>> worst_;  // (error, vertex), stale entries skipped
  std::vector<std::uint32_t> around_, squareAfter_;
  std::vector<double> errorAfter_;
};

}  // namespace

std::uint32_t snapTexels(std::uint32_t n, std::span<const ChartVertex> vertices, const std::function<Vec3(const Vec2&)>& surfaceAt,
                         std::vector<Vec2>& q, std::vector<Vec3>& p, bool keepDiagonal) {
  if (n < 3 || vertices.empty()) return 0;
  return Snapper(n, vertices, surfaceAt, q, p, keepDiagonal).run();
}

}  // namespace isoatlas::atlas
