#include "multires/mesh_distance.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace isoatlas::multires {
namespace {

// Squared distance from p to triangle (a, b, c) (Ericson, Real-Time Collision Detection, 5.1.5).
double pointTriangleDistance2(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  auto d2of = [&](const Vec3& q) { return dot(p - q, p - q); };
  if (d1 <= 0 && d2 <= 0) return d2of(a);
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return d2of(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return d2of(a + ab * (d1 / (d1 - d3)));
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return d2of(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return d2of(a + ac * (d2 / (d2 - d6)));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return d2of(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
  const double denom = 1 / (va + vb + vc);
  return d2of(a + ab * (vb * denom) + ac * (vc * denom));
}

double faceArea(const Mesh& m, std::size_t f) {
  const auto t = m.face(f);
  return norm(cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]])) / 2;
}

}  // namespace

TriangleGrid::TriangleGrid(const Mesh& mesh) : mesh_(mesh) {
  require(mesh.faceCount() > 0 && mesh.allFacesHave(3), "distance: needs a triangle mesh with faces");
  const Box box = boundingBox(mesh.positions);
  double area = 0;
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) area += faceArea(mesh, f);
  // Cells about twice a triangle's size, but at most 4096 along the box's diagonal (the cell key
  // packs 21 bits per axis).
  cell_ = std::max({2 * std::sqrt(area / double(mesh.faceCount())), box.diagonal() / 4096, 1e-9});
  origin_ = box.min;
  for (int a = 0; a < 3; ++a) extent_[a] = cellOf(box.max[a], a) + 1;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto t = mesh.face(f);
    std::int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      const double mn = std::min({mesh.positions[t[0]][a], mesh.positions[t[1]][a], mesh.positions[t[2]][a]});
      const double mx = std::max({mesh.positions[t[0]][a], mesh.positions[t[1]][a], mesh.positions[t[2]][a]});
      lo[a] = cellOf(mn, a), hi[a] = cellOf(mx, a);
    }
    for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
      for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
        for (std::int64_t x = lo[0]; x <= hi[0]; ++x) entries.push_back({key(x, y, z), std::uint32_t(f)});
  }
  std::sort(entries.begin(), entries.end());
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (i == 0 || entries[i].first != entries[i - 1].first) {
      cellIndex_[entries[i].first] = std::uint32_t(offsets_.size());
      offsets_.push_back(std::uint32_t(i));
    }
    triangles_.push_back(entries[i].second);
  }
  offsets_.push_back(std::uint32_t(triangles_.size()));
}

std::int64_t TriangleGrid::cellOf(double x, int axis) const {
  return std::int64_t(std::floor((x - origin_[axis]) / cell_));
}
std::uint64_t TriangleGrid::key(std::int64_t x, std::int64_t y, std::int64_t z) const {
  return (std::uint64_t(x) * 2097152 + std::uint64_t(y)) * 2097152 + std::uint64_t(z);
}

double TriangleGrid::distance(const Vec3& p) const {
  std::int64_t c[3];
  for (int a = 0; a < 3; ++a) c[a] = std::clamp<std::int64_t>(cellOf(p[a], a), 0, extent_[a] - 1);
  // How far p lies outside the grid's box, per axis: shells start counting from the nearest cell.
  double outside2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double lo = origin_[a], hi = origin_[a] + double(extent_[a]) * cell_;
    const double d = p[a] < lo ? lo - p[a] : (p[a] > hi ? p[a] - hi : 0);
    outside2 += d * d;
  }
  double best2 = std::numeric_limits<double>::infinity();
  const std::int64_t maxRing = std::max({extent_[0], extent_[1], extent_[2]});
  for (std::int64_t r = 0; r <= maxRing; ++r) {
    // Every triangle not yet seen lies at least (r - 1) cells beyond p's own cell.
    const double reach = std::max(0.0, double(r - 1)) * cell_;
    const double bound = std::max(reach * reach, outside2);
    if (best2 < std::numeric_limits<double>::infinity() && best2 <= bound) break;
    for (std::int64_t z = c[2] - r; z <= c[2] + r; ++z) {
      if (z < 0 || z >= extent_[2]) continue;
      for (std::int64_t y = c[1] - r; y <= c[1] + r; ++y) {
        if (y < 0 || y >= extent_[1]) continue;
        const bool faceZY = std::abs(z - c[2]) == r || std::abs(y - c[1]) == r;
        for (std::int64_t x = c[0] - r; x <= c[0] + r; x += (faceZY ? 1 : std::max<std::int64_t>(1, 2 * r))) {
          if (x < 0 || x >= extent_[0]) continue;
          const auto it = cellIndex_.find(key(x, y, z));
          if (it == cellIndex_.end()) continue;
          for (std::uint32_t i = offsets_[it->second]; i < offsets_[it->second + 1]; ++i) {
            const auto t = mesh_.face(triangles_[i]);
            best2 = std::min(best2, pointTriangleDistance2(p, mesh_.positions[t[0]], mesh_.positions[t[1]],
                                                           mesh_.positions[t[2]]));
          }
        }
      }
    }
  }
  return std::sqrt(best2);
}

std::vector<Vec3> surfaceSamples(const Mesh& mesh, std::size_t facePoints) {
  std::vector<Vec3> samples = mesh.positions;
  double total = 0;
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) total += faceArea(mesh, f);
  if (!(total > 0) || facePoints == 0) return samples;
  const double perPoint = total / double(facePoints);
  double carry = 0;  // area not yet sampled, carried to the next face so small faces add up
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    carry += faceArea(mesh, f);
    const int k = int(carry / perPoint);
    if (k == 0) continue;
    carry -= k * perPoint;
    // A triangular lattice of about k points inside the face.
    const int n = std::max(1, int(std::ceil((std::sqrt(8.0 * k + 1) - 1) / 2)));
    const auto t = mesh.face(f);
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        const double u = (i + 1.0 / 3) / n, v = (j + 1.0 / 3) / n;
        samples.push_back(a + (b - a) * u + (c - a) * v);
      }
  }
  return samples;
}

namespace {
struct Extent {
  double max = 0, sum = 0;
};
Extent oneSided(const std::vector<Vec3>& samples, const TriangleGrid& grid) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, samples.size(), 1024), Extent{},
      [&](const tbb::blocked_range<std::size_t>& r, Extent e) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
          const double d = grid.distance(samples[i]);
          e.max = std::max(e.max, d), e.sum += d;
        }
        return e;
      },
      [](Extent a, const Extent& b) { return Extent{std::max(a.max, b.max), a.sum + b.sum}; });
}
}  // namespace

Hausdorff hausdorffDistance(const Mesh& a, const Mesh& b) {
  const std::size_t points = std::max<std::size_t>(100000, 2 * std::max(a.vertexCount(), b.vertexCount()));
  const TriangleGrid gridA(a), gridB(b);
  const std::vector<Vec3> samplesA = surfaceSamples(a, points), samplesB = surfaceSamples(b, points);
  const Extent ab = oneSided(samplesA, gridB), ba = oneSided(samplesB, gridA);
  return {ab.max, ba.max, ab.sum / double(samplesA.size()), ba.sum / double(samplesB.size())};
}

double psnrDb(double diagonal, double distance) {
  return distance > 0 ? 20 * std::log10(diagonal / distance) : std::numeric_limits<double>::infinity();
}

}  // namespace isoatlas::multires
