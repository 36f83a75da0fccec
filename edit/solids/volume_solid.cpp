#include "edit/solids/volume_solid.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "levelset/level_set.h"

namespace isoatlas::edit::dvt {

TreeFrame frameOf(const Volume& volume) {
  TreeFrame f;
  const std::int64_t largest = std::max({volume.dims[0], volume.dims[1], volume.dims[2]});
  f.voxelSplits = 0;
  while ((std::int64_t(1) << f.voxelSplits) < largest) ++f.voxelSplits;
  require(f.voxelSplits <= kMaxDepth / 3, "the volume is too large for a volume tree");
  f.spacing = volume.spacing, f.origin = volume.origin, f.direction = volume.direction;
  f.extent = volume.dims;
  return f;
}

TreeFrame frameAround(const Vec3& lo, const Vec3& hi, int voxelSplits) {
  TreeFrame f;
  f.voxelSplits = voxelSplits;
  const Vec3 size = hi - lo;
  const double side = std::max({size.x, size.y, size.z}) * 1.1;  // a margin, so the surface stays inside
  const double h = side / double(f.voxelsPerAxis());
  f.spacing = {h, h, h};
  const Vec3 centre = (lo + hi) * 0.5;
  const double first = -0.5 * side + 0.5 * h;  // voxel 0's centre, from the box's centre
  f.origin = centre + Vec3{first, first, first};
  return f;
}

VolumeSolid::VolumeSolid(const Volume& volume)
    : dims_(volume.dims), voxel_([&volume](std::int64_t i, std::int64_t j, std::int64_t k) { return volume.at(i, j, k); }),
      mask_(!isFloating(volume.type)), spacing_(volume.spacing) {
  buildTable();
}

VolumeSolid::VolumeSolid(const levelset::LevelSet& levelSet)
    : dims_(levelSet.geometry().dims), mask_(false), spacing_(levelSet.geometry().spacing) {
  const float* pool = levelSet.phiPoolOnHost();
  const levelset::PageManager& pages = levelSet.pages();
  voxel_ = [pool, &pages](std::int64_t i, std::int64_t j, std::int64_t k) { return double(pool[pages.poolTexel(i, j, k)]); };
  buildTable();
}

void VolumeSolid::buildTable() {
  const std::int64_t nx = dims_[0], ny = dims_[1], nz = dims_[2];
  table_.assign(std::size_t((nx + 1) * (ny + 1) * (nz + 1)), 0);
  auto at = [&](std::int64_t i, std::int64_t j, std::int64_t k) -> std::uint32_t& {
    return table_[std::size_t((k * (ny + 1) + j) * (nx + 1) + i)];
  };
  for (std::int64_t k = 1; k <= nz; ++k)
    for (std::int64_t j = 1; j <= ny; ++j)
      for (std::int64_t i = 1; i <= nx; ++i)
        at(i, j, k) = std::uint32_t(voxelField(i - 1, j - 1, k - 1) > 0) + at(i - 1, j, k) + at(i, j - 1, k) + at(i, j, k - 1) -
                      at(i - 1, j - 1, k) - at(i - 1, j, k - 1) - at(i, j - 1, k - 1) + at(i - 1, j - 1, k - 1);
}

double VolumeSolid::voxelField(std::int64_t i, std::int64_t j, std::int64_t k) const {
  if (i < 0 || j < 0 || k < 0 || i >= dims_[0] || j >= dims_[1] || k >= dims_[2]) return -1;
  const double v = voxel_(i, j, k);
  return mask_ ? (v != 0 ? 1.0 : -1.0) : v;
}

double VolumeSolid::field(const Vec3& index) const {
  const std::int64_t i = std::int64_t(std::floor(index.x)), j = std::int64_t(std::floor(index.y)), k = std::int64_t(std::floor(index.z));
  const double fx = index.x - double(i), fy = index.y - double(j), fz = index.z - double(k);
  double sum = 0;
  for (int c = 0; c < 8; ++c) {
    const double w = (c & 1 ? fx : 1 - fx) * (c & 2 ? fy : 1 - fy) * (c & 4 ? fz : 1 - fz);
    if (w != 0) sum += w * voxelField(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1));
  }
  return sum;
}

std::uint64_t VolumeSolid::insideIn(const std::array<std::int64_t, 3>& lo, const std::array<std::int64_t, 3>& hi) const {
  std::array<std::int64_t, 3> a, b;  // clipped to the volume, as table corners
  for (int x = 0; x < 3; ++x) {
    a[x] = std::clamp<std::int64_t>(lo[x], 0, dims_[x]);
    b[x] = std::clamp<std::int64_t>(hi[x] + 1, 0, dims_[x]);
    if (b[x] <= a[x]) return 0;
  }
  const std::int64_t nx = dims_[0], ny = dims_[1];
  auto t = [&](std::int64_t i, std::int64_t j, std::int64_t k) -> std::int64_t { return table_[std::size_t((k * (ny + 1) + j) * (nx + 1) + i)]; };
  return std::uint64_t(t(b[0], b[1], b[2]) - t(a[0], b[1], b[2]) - t(b[0], a[1], b[2]) - t(b[0], b[1], a[2]) + t(a[0], a[1], b[2]) +
                       t(a[0], b[1], a[2]) + t(b[0], a[1], a[2]) - t(a[0], a[1], a[2]));
}

CellClass VolumeSolid::classify(const TreeFrame& frame, const Cell& cell, double) const {
  const Vec3 c = frame.centreIndex(cell), s = frame.cellVoxels(cell.depth);
  std::array<std::int64_t, 3> lo, hi;  // the voxels the interpolation reads anywhere in the cell
  std::uint64_t voxels = 1;
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::int64_t(std::floor(c[a] - 0.5 * s[a]));
    hi[a] = std::int64_t(std::floor(c[a] + 0.5 * s[a])) + 1;
    voxels *= std::uint64_t(hi[a] - lo[a] + 1);
  }
  const std::uint64_t inside = insideIn(lo, hi);
  return inside == 0 ? CellClass::Outside : (inside == voxels ? CellClass::Inside : CellClass::Crossed);
}

// The slope along each axis is the larger of the two one-sided differences: phi is clamped a few
// voxels from its front, and a clamp only ever flattens it.
double VolumeSolid::distance(const Vec3& index, double f) const {
  Vec3 gradient;
  for (int a = 0; a < 3; ++a) {
    Vec3 step{0, 0, 0};
    step[a] = 1;
    gradient[a] = std::max(std::abs(field(index + step) - f), std::abs(f - field(index - step))) / spacing_[a];
  }
  const double slope = norm(gradient);
  return slope > 0 ? f / slope : f * std::min({spacing_.x, spacing_.y, spacing_.z});
}

float VolumeSolid::value(const TreeFrame& frame, const Cell& cell, double radius) const {
  const Vec3 c = frame.centreIndex(cell);
  const double f = field(c);
  return mask_ ? boundValue(f, 1.0) : boundValue(distance(c, f), radius);
}

LeafSample sampleAt(const VolumeTree& tree, const Vec3& index) {
  Vec3 lo{-0.5, -0.5, -0.5};
  Vec3 size;
  for (int a = 0; a < 3; ++a) size[a] = double(tree.frame.voxelsPerAxis());
  std::size_t n = 0;
  for (std::uint32_t d = 0; !tree.pointers[n].leaf(); ++d) {
    const int a = splitAxis(d);
    size[a] *= 0.5;
    const bool upper = index[a] >= lo[a] + size[a];
    if (upper) lo[a] += size[a];
    n = std::size_t(upper ? tree.pointers[n].right : tree.pointers[n].left);
  }
  return {tree.pointers[n].value, tree.cell(n).depth};
}

Volume sampleMask(const VolumeTree& tree, const std::array<std::int64_t, 3>& dims) {
  Volume out = Volume::zeros(dims, ScalarType::UInt8);
  out.spacing = tree.frame.spacing, out.origin = tree.frame.origin, out.direction = tree.frame.direction;
  tbb::parallel_for(std::int64_t(0), dims[2], [&](std::int64_t k) {
    for (std::int64_t j = 0; j < dims[1]; ++j)
      for (std::int64_t i = 0; i < dims[0]; ++i)
        if (sampleAt(tree, Vec3{double(i), double(j), double(k)}).value > 0) out.setValue(out.index(i, j, k), 1);
  });
  return out;
}

Volume sampleMask(const VolumeTree& tree) { return sampleMask(tree, tree.frame.grid()); }

std::array<std::int64_t, 3> fieldGrid(std::uint32_t depth) {
  std::array<std::int64_t, 3> dims;
  for (int a = 0; a < 3; ++a) dims[a] = std::int64_t(1) << splitsOf(a, depth);
  return dims;
}

Volume sampleField(const VolumeTree& tree, std::uint32_t depth) {
  const TreeFrame& f = tree.frame;
  const Vec3 s = f.cellVoxels(depth);
  const std::array<std::int64_t, 3> dims = fieldGrid(depth);
  Volume out = Volume::zeros(dims, ScalarType::Float32);
  out.spacing = {f.spacing.x * s.x, f.spacing.y * s.y, f.spacing.z * s.z};
  out.direction = f.direction;
  out.origin = f.centreWorld(Cell{0, 0, 0, depth});
  std::vector<double> radius(kMaxDepth + 1);
  for (std::uint32_t d = 0; d <= std::uint32_t(kMaxDepth); ++d) radius[d] = f.radius(d);
  auto* data = reinterpret_cast<float*>(out.data.data());
  tbb::parallel_for(std::int64_t(0), dims[2], [&](std::int64_t k) {
    for (std::int64_t j = 0; j < dims[1]; ++j)
      for (std::int64_t i = 0; i < dims[0]; ++i) {
        const LeafSample l = sampleAt(tree, f.centreIndex(Cell{std::uint32_t(i), std::uint32_t(j), std::uint32_t(k), depth}));
        data[out.index(i, j, k)] = float(l.value * radius[l.depth]);
      }
  });
  return out;
}

}  // namespace isoatlas::edit::dvt
