#include "multires/base_domain.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"

namespace isoatlas::multires {
namespace {

int cornerOf(const std::array<std::uint32_t, 3>& t, std::uint32_t vertex) {
  for (int i = 0; i < 3; ++i)
    if (t[i] == vertex) return i;
  return -1;
}

}  // namespace

BaseDomain::BaseDomain(const BaseMesh& base)
    : base_(base),
      across_(base.triangleNeighbours()),
      stars_(vertexFaces(base.vertexCount(), base.triangleCount(), [&](std::size_t t) { return base.triangles[t]; })) {}

bool BaseDomain::inTriangle(std::uint32_t t, const Bary& bary, std::uint32_t u, Bary& out) const {
  if (u == t) {
    out = bary;
    return true;
  }
  out = {0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    if (bary[i] == 0) continue;
    const int at = cornerOf(base_.triangles[u], base_.triangles[t][i]);
    if (at < 0) return false;
    out[at] = bary[i];
  }
  return true;
}

bool BaseDomain::inStar(std::uint32_t vertex, std::uint32_t t, const Bary& bary, std::uint32_t& into, Bary& out) const {
  if (cornerOf(base_.triangles[t], vertex) >= 0) {
    into = t, out = bary;
    return true;
  }
  for (const std::uint32_t s : stars_.of(vertex))
    if (inTriangle(t, bary, s, out)) {
      into = s;
      return true;
    }
  return false;
}

bool BaseDomain::unfold(std::uint32_t from, const Bary& bary, std::uint32_t to, Bary& out) const {
  const auto& f = base_.triangles[from];
  const auto& t = base_.triangles[to];
  out = {0, 0, 0};
  int apex = -1, shared = 0;
  double apexWeight = 0;
  for (int i = 0; i < 3; ++i) {
    const int at = cornerOf(t, f[i]);
    if (at >= 0) out[at] += bary[i], ++shared;
    else apexWeight = bary[i];
  }
  for (int j = 0; j < 3; ++j)
    if (cornerOf(f, t[j]) < 0) apex = j;
  if (shared != 2 || apex < 0) return false;
  // from's apex -> (a + b - to's apex): add its weight to both shared corners, take it from the apex.
  for (int j = 0; j < 3; ++j) out[j] += j == apex ? -apexWeight : apexWeight;
  return true;
}

void BaseDomain::starChart(std::uint32_t vertex, std::uint32_t someTriangle, Chart& chart) const {
  // Triangle t holds `vertex` at corner i; counter-clockwise around it, t's sides are (vertex, t[i+1])
  // then (vertex, t[i+2]); the next triangle lies across edge i+2, the previous across edge i.
  auto corner = [&](std::uint32_t t) { return cornerOf(base_.triangles[t], vertex); };
  std::uint32_t first = someTriangle;
  for (std::size_t guard = 0; guard < 256; ++guard) {  // back to the boundary, if there is one
    const std::uint32_t previous = across_[first][corner(first)];
    if (previous == kNone || previous == someTriangle) break;
    first = previous;
  }
  chart.home = someTriangle;
  chart.vertex = vertex;
  chart.star.clear();
  chart.closed = false;
  for (std::uint32_t t = first; t != kNone && chart.star.size() < 256;) {
    chart.star.push_back(t);
    t = across_[t][(corner(t) + 2) % 3];
    if (t == first) {
      chart.closed = true;
      break;
    }
  }
  // The domain's metric is the unfold's: every base triangle equilateral, so a star of k triangles
  // is a cone of k * 60 degrees, laid flat by scaling its angles to a full turn (half on the boundary).
  chart.step = (chart.closed ? 2 : 1) * std::numbers::pi / double(chart.star.size());
}

bool BaseDomain::chartFor(const std::uint32_t* triangles, const Bary* bary, std::size_t n, std::uint32_t home, Chart& chart) const {
  std::uint32_t other = kNone;
  bool many = false;
  for (std::size_t i = 0; i < n; ++i) {
    if (triangles[i] == home || triangles[i] == other) continue;
    if (other == kNone) other = triangles[i];
    else many = true;
  }
  if (!many) {
    chart = {};
    chart.home = home;
    return true;
  }
  for (const std::uint32_t vertex : base_.triangles[home]) {
    bool shared = true;
    std::uint32_t into;
    Bary w;
    for (std::size_t i = 0; i < n && shared; ++i) shared = inStar(vertex, triangles[i], bary[i], into, w);
    if (!shared) continue;
    starChart(vertex, home, chart);
    return true;
  }
  return false;
}

bool BaseDomain::chartDenseTriangle(std::span<const std::uint32_t> corners, Chart& chart,
                                    std::array<Point2, 3>& points) const {
  std::uint32_t from[3];
  Bary bary[3];
  for (int i = 0; i < 3; ++i) {
    from[i] = base_.denseTriangle[corners[std::size_t(i)]];
    bary[i] = base_.denseBary[corners[std::size_t(i)]];
  }
  // One base triangle holding all three corners (a corner on a base vertex lies in every triangle
  // around it): its own frame draws the triangle exactly. A mesh that is its own base needs it: each
  // corner is a base vertex, placed in any one triangle around it, and three such triangles may
  // share no vertex.
  auto holdsAll = [&](std::uint32_t u) {
    Bary w[3];
    for (int i = 0; i < 3; ++i)
      if (!inTriangle(from[i], bary[i], u, w[i])) return false;
    chart = {};
    chart.home = u;
    for (int i = 0; i < 3; ++i) toChart(chart, u, w[i], points[std::size_t(i)]);
    return true;
  };
  for (int i = 0; i < 3; ++i) {
    if (holdsAll(from[i])) return true;
    for (int k = 0; k < 3; ++k)
      if (bary[i][std::size_t(k)] == 1)
        for (const std::uint32_t u : stars_.of(base_.triangles[from[i]][std::size_t(k)]))
          if (holdsAll(u)) return true;
  }
  if (!chartFor(from, bary, 3, from[0], chart)) return false;
  for (int i = 0; i < 3; ++i)
    if (!toChart(chart, from[i], bary[i], points[std::size_t(i)])) return false;
  return true;
}

namespace {
// Triangle k of a star chart: its outer corners' directions.
void starPiece(const BaseDomain::Chart& chart, std::size_t k, double (&a)[2], double (&b)[2]) {
  a[0] = std::cos(double(k) * chart.step), a[1] = std::sin(double(k) * chart.step);
  b[0] = std::cos(double(k + 1) * chart.step), b[1] = std::sin(double(k + 1) * chart.step);
}
}  // namespace

bool BaseDomain::toChart(const Chart& chart, std::uint32_t t, const Bary& bary, Point2& out) const {
  if (chart.vertex == kNone) {
    Bary b;
    if (!transfer(t, bary, chart.home, b)) return false;
    out = {b[1], b[2]};
    return true;
  }
  std::uint32_t s;
  Bary w;
  if (!inStar(chart.vertex, t, bary, s, w)) return false;
  const auto k = std::find(chart.star.begin(), chart.star.end(), s);
  if (k == chart.star.end()) return false;
  double a[2], b[2];
  starPiece(chart, std::size_t(k - chart.star.begin()), a, b);
  const int i = cornerOf(base_.triangles[s], chart.vertex);
  const double wa = w[(i + 1) % 3], wb = w[(i + 2) % 3];
  out = {wa * a[0] + wb * b[0], wa * a[1] + wb * b[1]};
  return true;
}

bool BaseDomain::inFrame(const Chart& chart, const Point2& p, std::uint32_t t, Bary& out) const {
  if (chart.vertex == kNone) return transfer(chart.home, {1 - p.x - p.y, p.x, p.y}, t, out);
  const auto k = std::find(chart.star.begin(), chart.star.end(), t);
  if (k == chart.star.end()) return false;
  double a[2], b[2];
  starPiece(chart, std::size_t(k - chart.star.begin()), a, b);
  const double det = a[0] * b[1] - a[1] * b[0];
  const double wa = (p.x * b[1] - p.y * b[0]) / det, wb = (a[0] * p.y - a[1] * p.x) / det;
  const int i = cornerOf(base_.triangles[t], chart.vertex);
  out[i] = 1 - wa - wb;
  out[(i + 1) % 3] = wa;
  out[(i + 2) % 3] = wb;
  return true;
}

bool BaseDomain::transfer(std::uint32_t from, const Bary& bary, std::uint32_t to, Bary& out) const {
  if (from == to) {
    out = bary;
    return true;
  }
  const auto& f = base_.triangles[from];
  const auto& t = base_.triangles[to];
  int shared = 0;
  std::uint32_t common = kNone;
  for (int i = 0; i < 3; ++i)
    if (cornerOf(t, f[i]) >= 0) ++shared, common = f[i];
  if (shared == 2) return unfold(from, bary, to, out);
  if (shared != 1) return false;
  Chart chart;
  starChart(common, to, chart);
  Point2 p;
  return toChart(chart, from, bary, p) && inFrame(chart, p, to, out);
}

}  // namespace isoatlas::multires
