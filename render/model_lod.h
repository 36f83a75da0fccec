// ModelLod: the CPU stage of the cascade for one model. It holds the model's adaptive mesh at its
// base tiles; an instance keeps its own copy (start()) from frame to frame, which adapt() takes to a
// request: uniformly to a level (rebuilt when the level changes), or to an error on the screen of a
// camera, the model placed at an offset, by welding where the new view allows and splitting where
// it asks (cpu_level.h); patchesOf() gives its patch list. patches() and refined() do all three for
// a single view.
#pragma once
#include <array>
#include <vector>

#include "atlas/model_file.h"
#include "atlas/tile_sides.h"
#include "multires/adaptive_mesh.h"
#include "render/camera.h"
#include "render/gpu_patches.h"

namespace isoatlas::render {

struct CpuRefinement {
  enum class Mode { Level, Pixels } mode = Mode::Pixels;
  int level = 0;        // Level: every face to this level
  double pixels = 2;    // Pixels: split where leaving the split point out moves the surface more
};

struct CpuFigures {
  std::size_t splits = 0, welds = 0, faces = 0;
  double ms = 0;  // refinement and the patch list
};

class ModelLod {
public:
  // Keeps a reference to the model's atlas (the sampler of new vertices): the model must outlive it.
  explicit ModelLod(const atlas::Model& model);
  int maxLevel() const;  // the chart's texels: 2 log2(N - 1)
  multires::AdaptiveMesh start() const { return base_; }
  // Throws Error(BadInput) for a level outside 0..maxLevel() or an error that is not positive.
  CpuFigures adapt(multires::AdaptiveMesh& mesh, const CpuRefinement& cpu, const Camera& camera, const Vec3& offset) const;
  std::vector<GpuPatch> patchesOf(const multires::AdaptiveMesh& mesh) const;
  std::vector<GpuPatch> patches(const CpuRefinement& cpu, const Camera& camera, const Vec3& offset,
                                CpuFigures* figures = nullptr) const;
  multires::AdaptiveMesh refined(const CpuRefinement& cpu, const Camera& camera, const Vec3& offset) const;
  const std::vector<std::array<atlas::SideAcross, 4>>& sidesAcross() const { return across_; }

private:
  const atlas::Model* model_;
  multires::AdaptiveMesh base_;
  std::vector<std::array<atlas::SideAcross, 4>> across_;
  std::vector<bool> hasDetail_;  // per tile
};

}  // namespace isoatlas::render
