#include "viewer/segmentation_session.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/volume_io.h"
#include "levelset/fill_threads.h"
#include "pipeline/segmentation.h"

namespace isoatlas::viewer {

SegmentationSession::SegmentationSession(Volume source, levelset::Backend backend)
    : source_(std::move(source)), backend_(backend), window_(render::percentileWindow(source_, 1, 99.5)) {
  // Until probed: T in the middle of the source's window, eps a tenth of it.
  const render::IntensityWindow& w = window_;
  const levelset::SpeedParams start{.target = float((w.low + w.high) / 2), .width = float(std::max(1e-3, (w.high - w.low) / 10)),
                                    .alpha = float(pipeline::kDefaultAlpha)};
  levelSet_ = std::make_unique<levelset::LevelSet>(source_, start, levelset::LevelSetOptions{.backend = backend});
}

Vec3 SegmentationSession::toIndex(const Vec3& world) const {
  const Vec3 ijk = source_.worldToIndex(world);
  for (int a = 0; a < 3; ++a)
    require(ijk[a] >= -0.5 && ijk[a] <= double(source_.dims[a]) - 0.5,
            "the point " + std::to_string(world.x) + "," + std::to_string(world.y) + "," + std::to_string(world.z) +
                " (mm) lies outside the volume");
  return ijk;
}

double SegmentationSession::toVoxels(double radius) const {
  require(std::isfinite(radius) && radius > 0, "a radius must be > 0 mm");
  return radius / std::cbrt(source_.spacing.x * source_.spacing.y * source_.spacing.z);
}

void SegmentationSession::setTopology(levelset::Topology topology) {
  if (topology == topology_) return;
  const Runs now = currentRuns();
  topology_ = topology;
  levelSet_ = std::make_unique<levelset::LevelSet>(source_, levelSet_->params(),
                                                   levelset::LevelSetOptions{.backend = backend_, .topology = topology});
  restore(now);
}

void SegmentationSession::setParams(const levelset::SpeedParams& params) {
  levelset::validateParams(params);
  levelSet_->setParams(params);
  ++version_;  // phi is as it was
}

levelset::ProbeResult SegmentationSession::probe(const Vec3& world, double radius) {
  const levelset::ProbeResult r = levelset::probeSphere(source_, toIndex(world), std::max(1.0, toVoxels(radius)));
  levelset::SpeedParams p = params();
  p.target = float(r.suggestedTarget());
  p.width = float(std::max(r.suggestedWidth(), 1e-3));
  setParams(p);
  return r;
}

SegmentationSession::Runs SegmentationSession::currentRuns() const {
  const Volume mask = levelSet_->mask();
  Runs runs{0};
  bool inside = false;
  for (const std::byte b : mask.data) {
    const bool in = b != std::byte{0};
    if (in != inside) runs.push_back(0), inside = in;
    ++runs.back();
  }
  return runs;
}

void SegmentationSession::restore(const Runs& runs) {
  Volume mask = Volume::zeros(source_.dims, ScalarType::UInt8);
  mask.spacing = source_.spacing, mask.origin = source_.origin, mask.direction = source_.direction;
  std::size_t at = 0;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    if (r % 2 == 1) std::fill_n(mask.data.begin() + std::ptrdiff_t(at), runs[r], std::byte{1});
    at += runs[r];
  }
  levelSet_->setMask(mask);
  phiChanged();
}

void SegmentationSession::remember() {
  undo_.push_back(currentRuns());
  if (undo_.size() > kUndoLevels) undo_.erase(undo_.begin());
  redo_.clear();
}

void SegmentationSession::seed(const Vec3& world, double radius, bool add) {
  const Vec3 centre = toIndex(world);
  const double r = toVoxels(radius);
  remember();
  levelSet_->addSphere(centre, r, add);
  phiChanged();
}

std::int64_t SegmentationSession::fillThreads() {
  Volume mask = levelSet_->mask();
  const std::int64_t filled = levelset::fillThreads(mask);
  if (filled > 0) replaceMask(mask);
  return filled;
}

void SegmentationSession::replaceMask(const Volume& mask) {
  require(mask.dims == source_.dims, "a mask for the segmentation needs the source's voxel grid");
  remember();
  levelSet_->setMask(mask);
  phiChanged();
}

// The segmentation now goes on `to`, the one it goes back to leaves `from` (both stacks as they were
// when restoring fails).
void SegmentationSession::step(std::vector<Runs>& from, std::vector<Runs>& to) {
  if (from.empty()) return;
  Runs now = currentRuns();
  restore(from.back());
  from.pop_back();
  to.push_back(std::move(now));
}

void SegmentationSession::undo() { step(undo_, redo_); }
void SegmentationSession::redo() { step(redo_, undo_); }

int SegmentationSession::advance(double budgetMs) {
  if (!running()) return 0;
  phiChanged();  // before the steps: whatever they change, views made before them are stale
  const auto begin = std::chrono::steady_clock::now();
  int steps = 0;
  double ms = 0;
  do {
    // Runs of as many steps as the last frames' rate fits in the budget (at most a chain's: on the GPU
    // the pages are then managed there, levelset/gpu_page_chain.h), and never past the steps asked for.
    int n = std::clamp(int(budgetMs * stepsPerSecond_ / 1000), 1, levelset::kChainIterations);
    if (!running_) n = std::min(n, pendingSteps_);
    const int done = levelSet_->run({.maxIterations = n, .untilConverged = false}).iterations;
    steps += done;
    pendingSteps_ = std::max(0, pendingSteps_ - done);
    if (done < n) break;  // nothing left that can move
    ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count();
  } while (running() && ms < budgetMs);
  stepsPerSecond_ = ms > 0 ? 1000.0 * steps / ms : 0;
  return steps;
}

render::VoxelField SegmentationSession::phi() const { return render::pagedField(*levelSet_); }

void SegmentationSession::saveMask(const std::string& path) const { writeVolume(path, levelSet_->mask()); }

}  // namespace isoatlas::viewer
