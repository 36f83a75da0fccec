#include "pipeline/segmentation.h"

#include "core/progress.h"

namespace isoatlas::pipeline {

Segmentation segmentVolume(const Volume& volume, const SegmentationRequest& request) {
  Segmentation s;
  s.backend = request.backend;
  s.renderer = request.renderer;
  s.levelSet = std::make_unique<levelset::LevelSet>(volume, request.params,
                                                    levelset::LevelSetOptions{.backend = s.backend, .pageSize = request.pageSize});
  if (request.seedMask) s.levelSet->setMask(*request.seedMask);
  for (const Ball& b : request.seeds) s.levelSet->addSphere(b.centre, b.radius);
  Progress progress(request.label, std::uint64_t(request.maxIterations), "iterations");
  s.stats = s.levelSet->run({.maxIterations = request.maxIterations,
                             .untilConverged = request.untilConverged,
                             .progress = [&](int i, std::int64_t) { progress.update(std::uint64_t(i)); }});
  progress.finish();
  if (request.readPhi) {
    s.phi = s.levelSet->phi();
    s.mask = levelset::maskOf(s.phi);
  } else {
    s.mask = s.levelSet->mask();
  }
  for (std::size_t n = 0; n < s.mask.voxelCount(); ++n) s.insideVoxels += s.mask.data[n] != std::byte{0};
  return s;
}

nlohmann::json Segmentation::figures() const {
  return {{"backend", backend == levelset::Backend::Gpu ? "gpu" : "cpu"},
          {"renderer", renderer},
          {"iterations", stats.iterations},
          {"seconds", stats.seconds},
          {"converged", stats.converged},
          {"inside_voxels", insideVoxels},
          {"active_pages_peak", levelSet->pages().stats().peakActive},
          {"physical_bytes_peak", levelSet->physicalBytesPeak()}};
}

}  // namespace isoatlas::pipeline
