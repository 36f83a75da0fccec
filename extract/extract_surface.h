// extractSurface: the closed, manifold isosurface of a volume in world coordinates, from a level set
// (phi, iso 0, inside > 0), a mask, or any scalar volume at any isovalue.
//   A binary mask (an integer volume with at most two values, and no iso given) is first made a smooth field: the
//   mask as 0/1 blurred by a Gaussian of sigma 1 voxel, taken at 0.5, so the surface follows the
//   mask without stair steps and encloses about the mask's volume.
//   Blocks of cells with no value above and none at or below iso are skipped (or, for a LevelSet,
//   every block away from its active pages), so the cost follows the surface.
// Options: keep the largest component or the components of at least N triangles; Taubin smoothing.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "core/mesh.h"
#include "core/volume.h"
#include "extract/gpu_marching_cubes.h"
#include "levelset/level_set.h"

namespace isoatlas::extract {

struct ExtractOptions {
  std::optional<float> iso;        // default: 0.5 for a mask, 0 for a level set, the mid value otherwise
  std::size_t largestComponents = 0;  // keep only this many, the largest (0: every one)
  std::int64_t minComponentTriangles = 0;
  int smoothIterations = 0;        // Taubin (lambda 0.5, mu -0.53)
  levelset::Backend backend = levelset::Backend::Cpu;  // Gpu: marching cubes in compute shaders
};

struct ExtractStats {
  float iso = 0;
  bool binaryInput = false;
  std::string path;  // "gpu pages", "cpu pages" (from a level set's pages), "gpu dense", "cpu dense"
  std::int64_t cellsVisited = 0, cellsTotal = 0;
  std::int64_t componentsRemoved = 0;
  std::uint64_t gpuBytes = 0;  // GPU memory the extraction allocated (GPU paths)
  double seconds = 0;
};

Mesh extractSurface(const Volume& volume, const ExtractOptions& options, ExtractStats* stats = nullptr);
// From the level set's pages, where its backend keeps them, with no dense phi on the host or the
// GPU: on the GPU (the Gpu backend and a GPU level set) the shaders read the solver's pool texture in the
// current GL context; otherwise the CPU reads the pool on the host (the GPU's read back once).
Mesh extractLevelSet(const levelset::LevelSet& levelSet, const ExtractOptions& options, ExtractStats* stats = nullptr);
// The same from a dense phi (levelSet.phi()), over the same blocks: the reference the paged path is
// tested and benchmarked against.
Mesh extractLevelSet(const levelset::LevelSet& levelSet, const Volume& phi, const ExtractOptions& options,
                     ExtractStats* stats = nullptr);

// The level set's surface {phi = iso} left on the GPU, in mc's buffers, for drawing where it lies: a
// GPU level set's pool read in place, in its GL context (current). Nothing after marching cubes (no
// components kept, no smoothing); positions in voxel index coordinates (the level set's geometry
// maps them to the world). Throws Error(Failure) for a level set whose phi is not on the GPU.
GpuSurface marchLevelSetOnGpu(const levelset::LevelSet& levelSet, GpuMarchingCubes& mc, float iso = 0);

// Whether a volume is a mask: integer voxels with at most two distinct values.
bool isBinaryMask(const Volume& volume);

}  // namespace isoatlas::extract
