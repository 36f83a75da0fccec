#include "render/model_lod.h"

#include <chrono>
#include <cmath>

#include "atlas/reconstruct.h"
#include "core/error.h"
#include "render/cpu_level.h"

namespace isoatlas::render {
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

CpuFigures ModelLod::adapt(multires::AdaptiveMesh& mesh, const CpuRefinement& cpu, const Camera& camera, const Vec3& offset) const {
  const auto start = std::chrono::steady_clock::now();
  CpuFigures f;
  if (cpu.mode == CpuRefinement::Mode::Level) {
    require(cpu.level >= 0 && cpu.level <= maxLevel(),
            "--cpu-level must lie between 0 and " + std::to_string(maxLevel()) + " for charts of " +
                std::to_string(model_->chartSize) + " texels");
    mesh = base_;
    f.splits = refineUniformly(mesh, cpu.level);
  } else {
    require(cpu.pixels > 0, "--cpu-error must be positive");
    const EdgeError onScreen = [&](const Vec3& sample, const Vec3& chord) {
      return norm(sample - chord) * camera.pixelsPerUnit(chord + offset);
    };
    f.welds = coarsenToError(mesh, onScreen, cpu.pixels);
    f.splits = refineToError(mesh, onScreen, cpu.pixels);
  }
  f.faces = mesh.mesh().n_faces();
  f.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return f;
}

std::vector<GpuPatch> ModelLod::patchesOf(const multires::AdaptiveMesh& mesh) const { return gpuPatches(mesh, across_, hasDetail_); }

multires::AdaptiveMesh ModelLod::refined(const CpuRefinement& cpu, const Camera& camera, const Vec3& offset) const {
  multires::AdaptiveMesh mesh = base_;
  adapt(mesh, cpu, camera, offset);
  return mesh;
}

std::vector<GpuPatch> ModelLod::patches(const CpuRefinement& cpu, const Camera& camera, const Vec3& offset,
                                        CpuFigures* figures) const {
  const auto start = std::chrono::steady_clock::now();
  multires::AdaptiveMesh mesh = base_;
  const CpuFigures f = adapt(mesh, cpu, camera, offset);
  std::vector<GpuPatch> out = patchesOf(mesh);
  if (figures) {
    *figures = f;
    figures->ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  return out;
}

}  // namespace isoatlas::render
