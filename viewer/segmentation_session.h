// SegmentationSession: the level set a window steers, as ITK-SNAP's snake mode does: T and eps probed
// from the source, seeds drawn in (model on) or out (model off), T, eps and alpha changed while it
// runs, a bounded number of steps per frame so the window stays responsive, edits undone and redone
// (the segmentation before each kept as a run-length-coded mask, kUndoLevels deep), the mask saved. No GL or UI here: the window's mouse and the scripted actions drive it alike. On
// the GPU backend the window's GL context must be current whenever the session is used.
// Points are world positions (mm, RAS); radii are in mm.
#pragma once
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/volume.h"
#include "levelset/level_set.h"
#include "levelset/probe.h"
#include "render/slice_render.h"

namespace isoatlas::viewer {

class SegmentationSession {
public:
  SegmentationSession(Volume source, levelset::Backend backend);

  const Volume& source() const { return source_; }
  // The source's intensities between its 1st and 99.5th percentiles: the slices' and the transfer
  // function's window to start from.
  const render::IntensityWindow& window() const { return window_; }
  levelset::LevelSet& levelSet() { return *levelSet_; }
  const levelset::LevelSet& levelSet() const { return *levelSet_; }

  const levelset::SpeedParams& params() const { return levelSet_->params(); }
  void setParams(const levelset::SpeedParams& params);  // checked; takes effect at the next step
  // Free, or the seeds' topology kept (levelset::Topology; segment --topology): the level set is made
  // again for it, from the mask as it stands (phi's sub-voxel detail is not kept).
  void setTopology(levelset::Topology topology);
  levelset::Topology topology() const { return topology_; }
  // The threads of background a preserved front leaves filled (levelset/fill_threads.h), as segment
  // does once it has converged; undoable. Returns the voxels filled.
  std::int64_t fillThreads();
  // T = mean and eps = standard deviation of the source in a ball (Lefohn's probing); returns them.
  levelset::ProbeResult probe(const Vec3& world, double radius);
  // A ball drawn in (add) or carved out; undoable.
  void seed(const Vec3& world, double radius, bool add);
  // The segmentation replaced by a mask of the source's grid (a brush's result); undoable.
  void replaceMask(const Volume& mask);
  // Back to before the last seed, unseed or replaceMask, and forward again (until the next edit). The
  // level set restarts from the mask: phi's sub-voxel detail and steps taken since are not kept.
  void undo();
  void redo();
  bool canUndo() const { return !undo_.empty(); }
  bool canRedo() const { return !redo_.empty(); }
  static constexpr std::size_t kUndoLevels = 32;

  void start() { running_ = true; }
  void pause() { running_ = false, pendingSteps_ = 0; }
  bool running() const { return running_ || pendingSteps_ > 0; }
  void requestSteps(int n) { pendingSteps_ += n; }  // taken on the next advances, running or not
  // Steps while running (or while requested steps remain) for about `budgetMs`, at least one;
  // returns how many it took.
  int advance(double budgetMs);

  int iterations() const { return levelSet_->iterations(); }
  std::int64_t activePages() const { return std::int64_t(levelSet_->pages().activePages().size()); }
  double stepsPerSecond() const { return stepsPerSecond_; }
  // Bumped by every change of phi or the parameters: a view redraws when it moves.
  std::uint64_t version() const { return version_; }
  // Bumped by every change of phi alone: what is made from phi (its pages on the GPU) is made again.
  std::uint64_t phiVersion() const { return phiVersion_; }

  // phi voxel by voxel from the backend's pool (read back once on the GPU): valid until the next step.
  render::VoxelField phi() const;
  void saveMask(const std::string& path) const;

private:
  // A mask as the lengths of its runs of outside and inside voxels, in turn (outside first).
  using Runs = std::vector<std::uint64_t>;
  Runs currentRuns() const;
  void restore(const Runs& runs);
  void step(std::vector<Runs>& from, std::vector<Runs>& to);
  void remember();
  Vec3 toIndex(const Vec3& world) const;
  double toVoxels(double radius) const;

  Volume source_;
  levelset::Backend backend_;
  levelset::Topology topology_ = levelset::Topology::Free;
  render::IntensityWindow window_;
  std::unique_ptr<levelset::LevelSet> levelSet_;
  std::vector<Runs> undo_, redo_;  // the newest last
  bool running_ = false;
  int pendingSteps_ = 0;
  double stepsPerSecond_ = 0;
  std::uint64_t version_ = 0, phiVersion_ = 0;
  void phiChanged() { ++version_, ++phiVersion_; }
};

}  // namespace isoatlas::viewer
