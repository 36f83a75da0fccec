// LevelSet: the steerable segmentation. It owns the page manager and a backend (CPU or GPU), decodes
// each iteration's activation messages (releasing pages to the static inside/outside page, activating
// requested ones initialised to the value they had), and exposes the steering API: step, run until
// converged, change T/eps/alpha between steps, add or remove spheres at any time, start from spheres
// or a mask, read phi or the mask at any time.
// Coordinates are voxel indices; phi is in voxel units, > 0 inside (see speed.h).
#pragma once
#include <array>
#include <functional>
#include <memory>
#include <string>

#include "core/volume.h"
#include "core/volume_source.h"
#include "levelset/backend.h"
#include "levelset/page_manager.h"
#include "levelset/solver_backend.h"

namespace isoatlas::levelset {

struct LevelSetOptions {
  Backend backend = Backend::Cpu;
  int pageSize = 16;
  std::int32_t initialSlots = 1024;  // the physical pool grows past this when it must
  // An active page whose voxels changed by no more than this in an iteration, with every page around
  // it (its 3 x 3 x 3) doing the same, is settled: the next iterations skip it until a page around it
  // changes by more, is activated, or the speed or phi is changed from outside (speed.h). 0: every
  // active page every iteration.
  float settledChange = kSettledChange;
  // CPU backend only: as the band moves, give the active pages slots in page order again
  // (PageManager::renumberInPageOrder), so that each page's neighbours lie near it in the pool. phi is
  // the same either way; false only to compare.
  bool renumberPages = true;
  // Preserve: the model keeps the topology it starts with (a ball stays a sphere, two seeds two
  // components), as Han, Xu and Prince's level set (solver_backend.h). Steering (spheres, masks) is
  // not held to it.
  Topology topology = Topology::Free;
  // GPU backend: run() leaves the page manager's work to the GPU (levelset/gpu_page_chain.h), the host
  // reading a small state block every kChainIterations iterations instead of the messages every
  // iteration. phi is the same bit for bit; false: the host applies each iteration's messages, as
  // step() always does (to compare).
  bool pagesOnDevice = true;
};

// --topology's words: "free" or "preserve"; throws Error (bad input) for another, naming `option`
// (the command's "--topology", Python's "topology=").
Topology topologyFor(const std::string& word, const std::string& option = "--topology");
inline constexpr std::array<const char*, 2> kTopologyChoices{"free", "preserve"};

struct RunOptions {
  int maxIterations = 1000;
  bool untilConverged = true;
  // Converged (windowConverged): over the last `window` iterations, fewer voxels changed side than
  // `changedVoxels`, or than `changedShare` of the active pages' voxels, whichever is more. The share
  // keeps the test the same for a large surface as for a small one: a front whose last voxels settle
  // one by one is done long before ten voxels in a whole brain stop flickering.
  int window = 20;
  std::int64_t changedVoxels = 10;
  double changedShare = 5e-5;
  std::function<void(int iteration, std::int64_t activePages)> progress;
};
bool windowConverged(std::int64_t changesInWindow, std::int64_t activeVoxels, const RunOptions& options);

struct RunStats {
  int iterations = 0;
  bool converged = false;
  double seconds = 0;
  std::uint64_t bytesReadBackPerIteration = 0;
  double simulatedTime = 0;  // sum of dt
};

class LevelSet {
public:
  // source: the intensities the speed reads (any scalar type; finite values), copied (as bytes where
  // every voxel is a whole number from 0 to 255, else as floats).
  LevelSet(const Volume& source, const SpeedParams& params, const LevelSetOptions& options = {});
  // The same read from `source` page by page as the band reaches them (core/volume_source.h): the
  // CPU solver holds the active pages' intensities besides what the source holds (the GPU's run on
  // the device, gpu_page_chain.h, the whole volume on the GPU). Finite values expected: a non-finite
  // one makes its page's speed so.
  LevelSet(std::shared_ptr<const VolumeSource> source, const SpeedParams& params, const LevelSetOptions& options = {});
  ~LevelSet();

  void setParams(const SpeedParams& params);  // takes effect at the next step
  const SpeedParams& params() const { return params_; }

  // Model on (add) or model off (remove) a ball of `radius` voxels around `centre` (voxel index).
  void addSphere(const Vec3& centre, double radius, bool add = true);
  // Starts over from a mask (voxels > 0 inside; same dims as the source).
  void setMask(const Volume& mask);

  IterationResult step();
  RunStats run(const RunOptions& options);

  Volume phi() const;   // float32, the source's geometry; inactive pages read as +-kClamp
  Volume mask() const;  // maskOf(phi()), made page by page with no dense phi
  // phi where the backend keeps it, for readers that follow the pages (extraction): the pool on the
  // host (the GPU's read back) and, on the GPU, its texture (0 on the CPU). See SolverBackend.
  const float* phiPoolOnHost() const { return backend_->phiPoolOnHost(); }
  unsigned phiPoolTexture() const { return backend_->phiPoolTexture(); }

  const PageManager& pages() const { return *pages_; }
  const Volume& geometry() const { return geometry_; }  // the source's dims, spacing, origin, direction; no voxels
  std::string backendName() const { return backend_->name(); }
  std::uint64_t physicalBytes() const { return backend_->physicalBytes(); }
  std::uint64_t physicalBytesPeak() const { return physicalBytesPeak_; }
  int iterations() const { return iterations_; }
  double simulatedTime() const { return simulatedTime_; }

private:
  void applyMessages(const IterationResult& r);
  // Which active pages the next iteration evaluates (one byte each, activePages() order): all of
  // them after a change from outside, else those with a moved page in their 3 x 3 x 3.
  std::vector<std::uint8_t> pagesToEvaluate();
  void markMoved(std::int64_t page);
  // A volume of the source's geometry from the pages: static pages as +-kClamp, active ones as read
  // back (one read of the active slots), each value through convert.
  template <class T, class Convert>
  Volume dense(ScalarType type, Convert convert) const;
  void commit(const std::vector<std::pair<std::int32_t, float>>& filled);
  void renumberWhenScattered();
  // run() on the backend alone (SolverBackend::runOnDevice); false where it cannot.
  bool runOnDevice(const RunOptions& options, RunStats& stats);

  Volume geometry_;  // the source's geometry, no data
  SpeedParams params_;
  std::unique_ptr<PageManager> pages_;
  std::unique_ptr<SolverBackend> backend_;
  std::vector<std::uint32_t> mark_;  // per virtual page: the iteration that last requested it
  float settledChange_;
  bool wakeAll_ = true;                  // the next iteration evaluates every active page
  bool renumberPages_ = false;           // the CPU backend's pool: slots kept in page order (renumberWhenScattered)
  bool pagesOnDevice_ = false;           // run() asks the backend to run on its own first (LevelSetOptions)
  std::vector<std::uint8_t> movedPage_;  // per virtual page: it moved in the last iteration, or was activated
  std::vector<std::int64_t> movedList_;  // the pages movedPage_ marks
  std::vector<std::uint8_t> wake_;       // per virtual page, within pagesToEvaluate
  std::vector<std::uint8_t> evaluateNext_;  // after a run on the device: its pagesToEvaluate, found there
  std::uint32_t epoch_ = 0;
  int iterations_ = 0;
  double simulatedTime_ = 0;
  std::uint64_t physicalBytesPeak_ = 0;
};

// Checks T, eps and alpha; throws Error (bad input) naming the value.
void validateParams(const SpeedParams& params);

// A mask voxel from phi: 1 inside (phi > 0), 0 outside.
inline std::uint8_t maskValue(float phi) { return phi > 0 ? 1 : 0; }
// uint8, maskValue of every voxel, in phi's geometry.
Volume maskOf(const Volume& phi);

}  // namespace isoatlas::levelset
