#include "extract/extract_surface.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <set>

#include "core/error.h"
#include "core/gl/stage_profile.h"
#include "extract/marching_cubes.h"
#include "extract/mesh_filters.h"
#include "levelset/level_set.h"

namespace isoatlas::extract {
namespace {

constexpr int kBlock = 8;

// Separable Gaussian (sigma 1 voxel, radius 3) of a 0/1 field, in place.
void gaussianBlur(std::vector<float>& f, const std::array<std::int64_t, 3>& dims) {
  float w[7];
  float sum = 0;
  for (int i = -3; i <= 3; ++i) sum += w[i + 3] = std::exp(-0.5f * float(i * i));
  for (float& x : w) x /= sum;
  std::vector<float> tmp(f.size());
  const std::int64_t stride[3] = {1, dims[0], dims[0] * dims[1]};
  for (int axis = 0; axis < 3; ++axis) {
    for (std::int64_t z = 0; z < dims[2]; ++z)
      for (std::int64_t y = 0; y < dims[1]; ++y)
        for (std::int64_t x = 0; x < dims[0]; ++x) {
          const std::int64_t p[3] = {x, y, z};
          const std::size_t n = std::size_t((z * dims[1] + y) * dims[0] + x);
          float acc = 0;
          for (int i = -3; i <= 3; ++i) {
            const std::int64_t q = p[axis] + i;
            if (q < 0 || q >= dims[axis]) continue;  // outside is 0: the mask is padded with outside
            acc += w[i + 3] * f[std::size_t(std::int64_t(n) + i * stride[axis])];
          }
          tmp[n] = acc;
        }
    f.swap(tmp);
  }
}

// Index coordinates to world; triangles reversed where the index-to-world map mirrors space, so the
// normals still point outwards.
void toWorld(Mesh& mesh, const Volume& v) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.positions.size()), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) mesh.positions[i] = v.indexToWorld(mesh.positions[i]);
  });
  const Mat3& d = v.direction;
  const double det = dot(d.column(0), cross(d.column(1), d.column(2)));
  if (det < 0)
    for (std::size_t f = 0; f < mesh.faceCount(); ++f)
      std::swap(mesh.faceVertices[mesh.faceOffsets[f] + 1], mesh.faceVertices[mesh.faceOffsets[f] + 2]);
}

// Marching cubes on the GPU or the CPU over the visited blocks, then what every extraction does
// after it: components, world coordinates, smoothing, figures. `field` says where the values came
// from ("dense" or "pages") in s.path.
Mesh march(const Grid& grid, levelset::Backend backend, const char* field, const VisitBlock& visit, const Volume& geometry,
           const ExtractOptions& o, ExtractStats& s, std::chrono::steady_clock::time_point start) {
  s.path = std::string(backend == levelset::Backend::Gpu ? "gpu " : "cpu ") + field;
  // ISOATLAS_GL_PROFILE=1: the GPU path's stages (marching cubes prints its own first); the CPU path
  // has no GL context to finish, so none.
  gl::StageProfile profile("extract gpu");
  const bool gpu = backend == levelset::Backend::Gpu;
  if (gpu) profile.stage("marching cubes");
  MarchingResult result = marchingCubes(backend, grid, s.iso, kBlock, visit);
  s.cellsVisited = result.cellsVisited;
  s.gpuBytes = result.gpuBytes;
  s.cellsTotal = (geometry.dims[0] + 1) * (geometry.dims[1] + 1) * (geometry.dims[2] + 1);
  Mesh mesh = std::move(result.mesh);
  if (gpu) profile.stage("keep components (cpu)");
  s.componentsRemoved = keepComponents(mesh, o.largestComponents, o.minComponentTriangles);
  if (gpu) profile.stage("to world, smooth (cpu)");
  toWorld(mesh, geometry);
  taubinSmooth(mesh, o.smoothIterations);
  profile.end();
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return mesh;
}

}  // namespace

bool isBinaryMask(const Volume& v) {
  if (isFloating(v.type)) return false;
  std::set<double> values;
  for (std::size_t n = 0; n < v.voxelCount(); ++n) {
    values.insert(v.value(n));
    if (values.size() > 2) return false;
  }
  return true;
}

Mesh extractSurface(const Volume& volume, const ExtractOptions& o, ExtractStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  ExtractStats local;
  ExtractStats& s = stats ? *stats : local;
  require(volume.voxelCount() > 0, "the volume is empty");
  require(o.smoothIterations >= 0, "--smooth must be >= 0");
  s.binaryInput = !o.iso && isBinaryMask(volume);  // an explicit isovalue means a scalar field
  // Float volumes are read in place; others (and masks, which are blurred) as a float copy.
  std::vector<float> field;
  if (volume.type != ScalarType::Float32 || s.binaryInput) field = volume.toFloat();
  if (s.binaryInput) {
    const ValueRange r = valueRange(volume);
    for (float& x : field) x = x > float(r.min) || r.min == r.max ? (x > 0 ? 1.0f : 0.0f) : 0.0f;
    gaussianBlur(field, volume.dims);
    s.iso = 0.5f;  // the blurred 0/1 field's midpoint (an explicit --iso means a scalar field)
  } else if (o.iso) {
    s.iso = *o.iso;
  } else {
    const ValueRange r = valueRange(volume);
    s.iso = float(0.5 * (r.min + r.max));
  }
  require(std::isfinite(s.iso), "the isovalue must be finite");
  // Taken only now: the blur swaps the field's buffer.
  const Grid grid{volume.dims, field.empty() ? reinterpret_cast<const float*>(volume.data.data()) : field.data()};
  // No blocks named: those that straddle iso are visited, the only ones with surface.
  return march(grid, o.backend, "dense", {}, volume, o, s, start);
}

namespace {

// The blocks of cells that touch an active page: everywhere else phi is flat.
VisitBlock activeBlocks(const levelset::PageManager& pm) {
  const int P = pm.pageSize();
  const auto d = pm.dims();
  const std::array<std::int64_t, 3> blocks{blockCount(d[0], kBlock), blockCount(d[1], kBlock), blockCount(d[2], kBlock)};
  auto mark = std::make_shared<std::vector<char>>(std::size_t(blocks[0] * blocks[1] * blocks[2]), 0);
  for (std::int64_t page : pm.activePages()) {
    const auto [px, py, pz] = pm.pageCoords(page);
    // Cells c - 1 and c touch voxel c, and cell c lies in block (c + 1) / kBlock: so the page's
    // voxels [v0, v1] are touched by the blocks [v0 / kBlock, (v1 + 1) / kBlock] on each axis.
    for (std::int64_t z = pz / kBlock; z <= std::min(blocks[2] - 1, (pz + 1) / kBlock); ++z)
      for (std::int64_t y = (py * P) / kBlock; y <= std::min(blocks[1] - 1, (py * P + P) / kBlock); ++y)
        for (std::int64_t x = (px * P) / kBlock; x <= std::min(blocks[0] - 1, (px * P + P) / kBlock); ++x)
          (*mark)[std::size_t((z * blocks[1] + y) * blocks[0] + x)] = 1;
  }
  return [mark, blocks](std::int64_t bx, std::int64_t by, std::int64_t bz) {
    return (*mark)[std::size_t((bz * blocks[1] + by) * blocks[0] + bx)] != 0;
  };
}

}  // namespace

Mesh extractLevelSet(const levelset::LevelSet& ls, const ExtractOptions& o, ExtractStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  ExtractStats local;
  ExtractStats& s = stats ? *stats : local;
  s.iso = o.iso.value_or(0.0f);
  // The GPU reads the pool where a GPU level set keeps it; a CPU level set's pool is on the host.
  const bool gpu = o.backend == levelset::Backend::Gpu && ls.phiPoolTexture() != 0;
  Grid grid{ls.pages().dims()};
  grid.paged.pages = &ls.pages();
  if (gpu) grid.pagedTexture = ls.phiPoolTexture();
  else grid.paged.pool = ls.phiPoolOnHost();
  return march(grid, gpu ? levelset::Backend::Gpu : levelset::Backend::Cpu, "pages", activeBlocks(ls.pages()), ls.geometry(), o, s, start);
}

GpuSurface marchLevelSetOnGpu(const levelset::LevelSet& ls, GpuMarchingCubes& mc, float iso) {
  if (ls.phiPoolTexture() == 0)
    throw Error("the level set's phi is not on the GPU: its surface can be left there only from a GPU level set", ErrorKind::Failure);
  Grid grid{ls.pages().dims()};
  grid.paged.pages = &ls.pages();
  grid.pagedTexture = ls.phiPoolTexture();
  return mc.march(grid, iso, kBlock, activeBlocks(ls.pages()));
}

Mesh extractLevelSet(const levelset::LevelSet& ls, const Volume& phi, const ExtractOptions& o, ExtractStats* stats) {
  require(phi.type == ScalarType::Float32 && phi.dims == ls.pages().dims(),
          "extractLevelSet: phi must be the level set's own (float, its dimensions)");
  const auto start = std::chrono::steady_clock::now();
  ExtractStats local;
  ExtractStats& s = stats ? *stats : local;
  s.iso = o.iso.value_or(0.0f);
  const Grid grid{phi.dims, reinterpret_cast<const float*>(phi.data.data())};
  return march(grid, o.backend, "dense", activeBlocks(ls.pages()), phi, o, s, start);
}

}  // namespace isoatlas::extract
