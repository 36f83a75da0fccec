// SolverBackend: one iteration of the paged solver over the active pages, on the CPU (cpu_solver) or
// the GPU (gpu_solver). Both keep phi in the PageManager's physical layout: a pool image of
// poolPagesX * P texels per row (a texture's width on the GPU, one slot on the CPU), slots 0/1 the
// static pages. The GPU ping-pongs two copies; the CPU updates one in place (its pass 1 has read
// everything before pass 2 writes).
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "levelset/page_manager.h"
#include "levelset/speed.h"

namespace isoatlas::levelset {

// Whether a voxel may change side freely (the seed's solver), or only where that keeps the object's
// topology (a simple point, levelset/simple_point.h; Han, Xu and Prince 2003). Preserve updates the
// voxels that would change side in eight parity classes of (x, y, z) mod 2, one after another: no two
// voxels of a class are neighbours, so each class's tests are independent and both backends give one
// answer whatever the order within a class.
enum class Topology { Free, Preserve };

struct IterationResult {
  std::vector<std::uint8_t> messages;  // one byte per active page, in PageManager::activePages() order
  std::vector<std::uint8_t> moved;     // per active page, the same order: 1 where a voxel's phi changed by more than settledChange
  std::int64_t signChanges = 0;        // voxels whose phi changed sign
  float maxSpeed = 0, dt = 0;
  std::uint64_t bytesReadBack = 0;     // GPU -> CPU this iteration
};

// Iterations a run on the device queues between two reads of its state (gpu_page_chain.h).
inline constexpr int kChainIterations = 16;
// The longest convergence window a run on the device tests (longer: the host drives).
inline constexpr int kChainRingSize = 64;

// A run of iterations the backend drives itself (SolverBackend::runOnDevice), and what it did.
struct DeviceRunRequest {
  int maxIterations = 0;
  bool untilConverged = true;
  int window = 20;  // windowConverged's test (level_set.h's RunOptions)
  double changedVoxels = 10, changedShare = 5e-5;
  std::function<void(int iteration, std::int64_t activePages)> progress;  // per iteration, a few at a time
};
struct DeviceRun {
  int iterations = 0;
  bool converged = false;  // stopped by the window's test, or with no page left
  std::vector<float> dt;   // per iteration
  std::vector<std::uint8_t> nextEvaluate;  // which active pages the next iteration evaluates (pm's order)
  std::uint64_t bytesReadBack = 0;
};

class SolverBackend {
public:
  virtual ~SolverBackend() = default;
  virtual std::string name() const = 0;
  // The active set changed: grow storage to pm.capacity(), fill each (slot, value) page with the
  // value, and refresh the per-page neighbour tables.
  virtual void pagesChanged(const PageManager& pm, const std::vector<std::pair<std::int32_t, float>>& filled) = 0;
  // One iteration over the active pages whose `evaluate` byte is 1 (one per active page, in
  // activePages() order). The others are settled: their phi stays and their speed is left out of the
  // step's CFL bound, as if no voxel of theirs moved.
  virtual IterationResult iterate(const PageManager& pm, const SpeedParams& params, const std::vector<std::uint8_t>& evaluate,
                                  float settledChange) = 0;
  // Iterations with the page manager's work done by the backend itself (LevelSet::run's loop, the
  // messages applied and the settled pages found without the host), the first evaluating the pages
  // `evaluate` says; pm takes the pages as they end. nullopt where the backend cannot (the CPU's, a
  // volume too large for the GPU's source buffer, a window past kChainRingSize): the host drives.
  virtual std::optional<DeviceRun> runOnDevice(PageManager&, const SpeedParams&, const std::vector<std::uint8_t>& /*evaluate*/,
                                               float /*settledChange*/, const DeviceRunRequest&) {
    return std::nullopt;
  }
  // P*P values per slot, row-major, from the current phi.
  virtual std::vector<float> readSlots(const PageManager& pm, const std::vector<std::int32_t>& slots) = 0;
  virtual void writeSlots(const PageManager& pm, const std::vector<std::int32_t>& slots, const std::vector<float>& values) = 0;
  // The whole current phi pool for readers in this process (extraction from the pages): rows of
  // poolPagesX * P texels, capacity / poolPagesX * P rows, slots where PageManager says (the static
  // pages included). On the host: the CPU's own storage, or the GPU's read back once per call; valid
  // until the backend is next used.
  virtual const float* phiPoolOnHost() = 0;
  // The GL texture (r32f) holding that pool, in the context the solver was made in; 0 on the CPU.
  virtual unsigned phiPoolTexture() const { return 0; }
  // The solver's memory: phi (both copies on the GPU), per-page tables, and the source it reads where
  // that lives in the same memory (the CPU: the active pages' intensities and what its VolumeSource
  // holds; the GPU: its source pages, and the whole source once a run manages its pages there).
  virtual std::uint64_t physicalBytes() const = 0;
};

}  // namespace isoatlas::levelset
