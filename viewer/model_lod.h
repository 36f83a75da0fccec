// ModelLod: the CPU stage of the cascade for one model. It holds the model's adaptive mesh at its
// base tiles and makes, per request, the patch list of a refined copy: uniformly to a level, or to
// an error on the screen of a camera (cpu_level.h), the model placed at an offset.
#pragma once
#include <array>
#include <vector>

#include "atlas/model_file.h"
#include "atlas/tile_sides.h"
#include "multires/adaptive_mesh.h"
#include "viewer/camera.h"
#include "viewer/gpu_patches.h"

namespace isoatlas::viewer {

struct CpuRefinement {
  enum class Mode { Level, Pixels } mode = Mode::Pixels;
  int level = 0;        // Level: every face to this level
  double pixels = 2;    // Pixels: split where leaving the split point out moves the surface more
};

struct CpuFigures {
  std::size_t splits = 0, faces = 0;
  double ms = 0;  // refinement and the patch list
};

class ModelLod {
public:
  // Keeps a reference to the model's atlas (the sampler of new vertices): the model must outlive it.
  explicit ModelLod(const atlas::Model& model);
  int maxLevel() const;  // the chart's texels: 2 log2(N - 1)
  std::vector<GpuPatch> patches(const CpuRefinement& cpu, const Camera& camera, const Vec3& offset,
                                CpuFigures* figures = nullptr) const;
  // The CPU mesh itself, for tests: refined as patches() would.
  multires::AdaptiveMesh refined(const CpuRefinement& cpu, const Camera& camera, const Vec3& offset,
                                 std::size_t* splits = nullptr) const;
  const std::vector<std::array<atlas::SideAcross, 4>>& sidesAcross() const { return across_; }

private:
  const atlas::Model* model_;
  multires::AdaptiveMesh base_;
  std::vector<std::array<atlas::SideAcross, 4>> across_;
  std::vector<bool> hasDetail_;  // per tile
};

}  // namespace isoatlas::viewer
