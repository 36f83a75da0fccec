// GpuPageChain: the page manager's work done on the GPU, so that the GPU level set runs iteration
// after iteration without the host (issue 63). After the solver's passes (speed, update, messages),
// six page passes (levelset/shaders/pages_*.comp) do what LevelSet::applyMessages and
// pagesToEvaluate do on the host:
//   request   each active page's message marks the pages it needs; the inactive ones are listed new
//   release   pages nobody requested go back to the static inside/outside page, slots onto the stack
//   plan      enough free slots? (else the chain stalls until the host grows the pool) and the grids
//             of the next passes, sized on the GPU (indirect dispatch)
//   activate  new pages take slots, start as the static page they were, get the source's intensities
//   entries   the page table the solver's passes read, and which pages the next iteration evaluates
//   end       the iteration logged, the counters reset, the chain stopped where LevelSet::run stops
// The host queues a few iterations, reads the small state block (PageState) once, and goes on. Slots
// are handed out in another order than the host's, which changes where phi lies in the pool, never its
// values: phi is the host-driven GPU path's bit for bit.
// The whole source volume lives in a GPU buffer (the new pages' intensities are copied from it), so
// the chain serves volumes whose floats fit one storage buffer (fits()); others keep the host path.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "core/gl/context.h"
#include "core/gl/resources.h"
#include "core/volume_source.h"
#include "levelset/page_manager.h"
#include "levelset/solver_backend.h"

namespace isoatlas::levelset {

inline constexpr int kChainLogSize = 64;   // iterations logged between two reads of the state

// Mirrors PageState in shaders/page_state.glsl (std430).
struct PageState {
  std::int32_t activeCount, keptCount, newCount, freeTop, epoch, stalled, stopped, iterations;
  std::uint32_t pageArgs[3], threadArgs[3], newArgs[3], wordArgs[3];
  std::int32_t activations, releases, peakActive, ringCount;
  std::int32_t ring[kChainRingSize];
  std::int32_t log[kChainLogSize][4];  // sign changes, dt's bits, active pages, 0
};
static_assert(offsetof(PageState, pageArgs) == 32 && offsetof(PageState, log) == 352);

// The convergence test the chain applies (RunOptions's).
struct ChainStop {
  bool untilConverged = true;
  int window = 20;
  double changedVoxels = 10, changedShare = 5e-5;
};

// The solver's storage the page passes write.
struct ChainTargets {
  GLuint phi, sourcePool;  // the current phi pool and the source's pages (r32f textures)
  const gl::Buffer &entries, &messages;
  gl::Buffer& evaluate;
  int movedOffset;  // where the moved bytes start in `messages`, in words
};

class GpuPageChain {
public:
  // Whether a volume of `voxels` floats fits the chain's source buffer in the current context.
  static bool fits(std::uint64_t voxels);
  // defines: the solver's (PAGE_SIZE, CLAMP, ...); source: the volume (of dims), uploaded whole to
  // the GPU a slice at a time (the host holds one slice of floats, not the volume).
  GpuPageChain(gl::Context& ctx, const gl::Defines& defines, std::array<std::int64_t, 3> pages, std::array<std::int64_t, 3> dims,
               const VolumeSource& source);

  // The page manager's state (page table, active list, free stack) onto the GPU, with the first
  // iteration's evaluate bytes already in the solver's buffer; the counters start at zero.
  void upload(const PageManager& pm);
  // The page passes of one iteration (after the solver's), or from `plan` on, for a stalled one.
  void pagePasses(const ChainTargets& targets, bool evaluateAll, const ChainStop& stop, bool fromPlan = false);
  PageState readState();
  // GPU memory the chain holds: the whole source volume, per-page tables and lists.
  std::uint64_t bytes() const;
  // The pool grew to `capacity` slots: the stack gets the new ones (lowest on top, as
  // PageManager::grow stacks them), and the stall is cleared.
  void grow(std::int32_t oldCapacity, std::int32_t capacity, const PageState& state);
  // The GPU's pages into `pm` (PageManager::adopt).
  void download(PageManager& pm, std::int32_t capacity, std::int64_t growths);

  const gl::Buffer& state() const { return state_; }
  std::int32_t capacity() const { return capacity_; }

private:
  void sizeSlots(std::int32_t capacity);
  gl::Context& ctx_;
  std::array<std::int64_t, 3> pages_, dims_;
  int pageSize_ = 0;
  std::int32_t capacity_ = 0;
  std::int32_t epoch_ = 1;  // the next iteration's: marks of earlier chains are always older
  gl::Buffer state_, pageTable_, marks_, activeList_, nextList_, newList_, freeStack_, source_;
  const gl::Program *request_, *release_, *plan_, *activate_, *entries_, *end_;
};

}  // namespace isoatlas::levelset
