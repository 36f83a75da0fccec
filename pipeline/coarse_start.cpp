#include "pipeline/coarse_start.h"

#include <tbb/parallel_for.h>

#include <algorithm>

namespace isoatlas::pipeline {
namespace {

std::array<std::int64_t, 3> halfDims(const std::array<std::int64_t, 3>& dims) {
  return {(dims[0] + 1) / 2, (dims[1] + 1) / 2, (dims[2] + 1) / 2};
}

// Calls f(x, y, z, X, Y, Z) for each voxel (X, Y, Z) of block (x, y, z)'s, within dims.
template <class F>
void forBlock(const std::array<std::int64_t, 3>& dims, std::int64_t x, std::int64_t y, std::int64_t z, F&& f) {
  for (std::int64_t Z = 2 * z; Z < std::min(2 * z + 2, dims[2]); ++Z)
    for (std::int64_t Y = 2 * y; Y < std::min(2 * y + 2, dims[1]); ++Y)
      for (std::int64_t X = 2 * x; X < std::min(2 * x + 2, dims[0]); ++X) f(X, Y, Z);
}

}  // namespace

Volume halfResolution(const VolumeSource& source) {
  const Volume& volume = source.geometry();
  const auto& d = volume.dims;
  Volume half = Volume::zeros(halfDims(d), ScalarType::Float32);
  half.spacing = volume.spacing * 2.0;
  half.direction = volume.direction;
  half.origin = volume.indexToWorld({0.5, 0.5, 0.5});
  auto* out = reinterpret_cast<float*>(half.data.data());
  tbb::parallel_for(std::int64_t(0), half.dims[2], [&](std::int64_t z) {
    // The block row's source rows (Y, Z), 2 x 2 of them, each read whole.
    std::vector<float> rows(std::size_t(4 * d[0]), 0.0f);
    for (std::int64_t y = 0; y < half.dims[1]; ++y) {
      for (std::int64_t Z = 2 * z; Z < std::min(2 * z + 2, d[2]); ++Z)
        for (std::int64_t Y = 2 * y; Y < std::min(2 * y + 2, d[1]); ++Y)
          source.readRow(0, Y, Z, d[0], rows.data() + ((Z - 2 * z) * 2 + (Y - 2 * y)) * d[0]);
      for (std::int64_t x = 0; x < half.dims[0]; ++x) {
        double sum = 0;
        int n = 0;
        forBlock(d, x, y, z, [&](std::int64_t X, std::int64_t Y, std::int64_t Z) {
          sum += rows[std::size_t(((Z - 2 * z) * 2 + (Y - 2 * y)) * d[0] + X)];
          ++n;
        });
        out[half.index(x, y, z)] = float(sum / n);
      }
    }
  });
  return half;
}

Volume halfResolution(const Volume& volume) { return halfResolution(*VolumeInMemory::compact(volume)); }

CoarseStart solveAtHalfResolution(const VolumeSource& source, const levelset::SpeedParams& params, const std::vector<Ball>& seeds,
                                  const Volume* seedMask, const levelset::LevelSetOptions& options,
                                  const levelset::RunOptions& run, const std::function<bool(const Volume&)>& acceptStart) {
  const Volume& volume = source.geometry();
  const Volume half = halfResolution(source);
  levelset::LevelSet coarse(half, params, options);
  if (seedMask) {
    Volume halfMask = half.sameGeometry(ScalarType::UInt8);
    for (std::int64_t z = 0; z < half.dims[2]; ++z)
      for (std::int64_t y = 0; y < half.dims[1]; ++y)
        for (std::int64_t x = 0; x < half.dims[0]; ++x) {
          bool inside = false;
          forBlock(volume.dims, x, y, z, [&](std::int64_t X, std::int64_t Y, std::int64_t Z) { inside |= seedMask->at(X, Y, Z) > 0; });
          halfMask.data[halfMask.index(x, y, z)] = std::byte(inside ? 1 : 0);
        }
    coarse.setMask(halfMask);
  }
  // Block (x, y, z) covers voxels 2x and 2x + 1, so voxel X lies at (X - 0.5) / 2; radii at least a voxel.
  for (const Ball& b : seeds) coarse.addSphere((b.centre - Vec3{0.5, 0.5, 0.5}) * 0.5, std::max(1.0, b.radius / 2));
  CoarseStart start;
  if (acceptStart && !acceptStart(coarse.mask())) {
    start.started = false;
    return start;
  }
  start.stats = coarse.run(run);
  const Volume halfMask = coarse.mask();
  start.mask = volume.sameGeometry(ScalarType::UInt8);
  tbb::parallel_for(std::int64_t(0), volume.dims[2], [&](std::int64_t Z) {
    for (std::int64_t Y = 0; Y < volume.dims[1]; ++Y)
      for (std::int64_t X = 0; X < volume.dims[0]; ++X)
        start.mask.data[volume.index(X, Y, Z)] = halfMask.data[halfMask.index(X / 2, Y / 2, Z / 2)];
  });
  return start;
}

CoarseStart solveAtHalfResolution(const Volume& volume, const levelset::SpeedParams& params, const std::vector<Ball>& seeds,
                                  const Volume* seedMask, const levelset::LevelSetOptions& options,
                                  const levelset::RunOptions& run, const std::function<bool(const Volume&)>& acceptStart) {
  return solveAtHalfResolution(*VolumeInMemory::compact(volume), params, seeds, seedMask, options, run, acceptStart);
}

}  // namespace isoatlas::pipeline
