#include "viewer/model_lod.h"

#include <chrono>
#include <cmath>

#include "atlas/reconstruct.h"
#include "core/error.h"
#include "viewer/cpu_level.h"

namespace isoatlas::viewer {
namespace {

multires::AdaptiveMesh::Sampler atlasSampler(const atlas::Atlas& atlas) {
  return [&atlas](const multires::ChartPoint& p) {
    const double n = atlas.layout.chartSize - 1;
    return atlas.position(p.chart, std::uint32_t(std::lround(p.u * n)), std::uint32_t(std::lround(p.v * n)));
  };
}

}  // namespace

ModelLod::ModelLod(const atlas::Model& model)
    : model_(&model), base_(model.base, model.chartSize, atlasSampler(model.atlas)), across_(atlas::sidesAcross(model.base)) {
  if (model.atlas.details.empty()) return;
  hasDetail_.assign(model.base.tiles.size(), false);
  for (const atlas::DetailChart& d : model.atlas.details) hasDetail_[d.tile] = true;
}

int ModelLod::maxLevel() const { return atlas::maxLevel(model_->chartSize); }

multires::AdaptiveMesh ModelLod::refined(const CpuRefinement& cpu, const Camera& camera, const Vec3& offset,
                                         std::size_t* splits) const {
  multires::AdaptiveMesh mesh = base_;
  std::size_t made = 0;
  if (cpu.mode == CpuRefinement::Mode::Level) {
    require(cpu.level >= 0 && cpu.level <= maxLevel(),
            "--cpu-level must lie between 0 and " + std::to_string(maxLevel()) + " for charts of " +
                std::to_string(model_->chartSize) + " texels");
    made = refineUniformly(mesh, cpu.level);
  } else {
    require(cpu.pixels > 0, "--cpu-error must be positive");
    made = refineToError(mesh, [&](const Vec3& sample, const Vec3& chord) {
      return norm(sample - chord) * camera.pixelsPerUnit(chord + offset);
    }, cpu.pixels);
  }
  if (splits) *splits = made;
  return mesh;
}

std::vector<GpuPatch> ModelLod::patches(const CpuRefinement& cpu, const Camera& camera, const Vec3& offset,
                                        CpuFigures* figures) const {
  const auto start = std::chrono::steady_clock::now();
  std::size_t splits = 0;
  const multires::AdaptiveMesh mesh = refined(cpu, camera, offset, &splits);
  std::vector<GpuPatch> out = gpuPatches(mesh, across_, hasDetail_);
  if (figures) {
    figures->splits = splits;
    figures->faces = mesh.mesh().n_faces();
    figures->ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  return out;
}

}  // namespace isoatlas::viewer
