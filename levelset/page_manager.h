// PageManager: the multidimensional virtual memory of the paged narrow-band solver (Lefohn's thesis,
// ch. 3; Hong & Park). Shared by the CPU and GPU backends; it owns no voxel data, only the mapping.
//   virtual space:  the volume split into P x P x 1 pages; (pagesX, pagesY, Z) of them
//   physical space: a 2D pool of page slots, poolPagesX slots per row; slot s has its texel origin
//                   at ((s % poolPagesX) * P, (s / poolPagesX) * P). Slots 0 and 1 are the static
//                   outside (phi = -clamp) and inside (phi = +clamp) pages every inactive page maps to.
//                   The GPU's pool is a texture 4096 texels wide (PoolLayout::Texture); the CPU's
//                   has one slot a row (PoolLayout::Contiguous), so that a page's P x P texels lie
//                   together in memory, its rows in neighbouring cache lines rather than a texture
//                   row apart.
//   page table:     virtual page -> slot; inverse page table: slot -> virtual page (or -1)
//   free stack:     unused slots; when it runs empty the pool grows by whole rows (slot origins stay
//                   put, so backends grow their storage by appending rows). An active page is never
//                   dropped to make room.
//   renumbering:    renumberInPageOrder gives the active pages the lowest slots in page order again;
//                   the backend moves their values (the CPU's level set, as slots scatter).
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace isoatlas::levelset {

// Pages are P x P voxels, P a power of two from 4 to this (the CPU backend's fixed-size scratch).
inline constexpr int kMaxPageSize = 32;
// Page sizes the manager takes: powers of two from 4 to kMaxPageSize.
inline bool isPageSize(int p) { return p >= 4 && p <= kMaxPageSize && (p & (p - 1)) == 0; }

constexpr std::int32_t kOutsideSlot = 0, kInsideSlot = 1;

enum class PoolLayout { Texture, Contiguous };
// Slots a row of the GPU's pool texture (PoolLayout::Texture): 4096 texels wide.
inline std::int32_t textureSlotsPerRow(int pageSize) { return 4096 / pageSize; }

class PageManager {
public:
  // dims: volume size in voxels; pageSize: P; initialSlots: pool size to start with (grows); layout:
  // how the slots lie in the pool.
  PageManager(std::array<std::int64_t, 3> dims, int pageSize, std::int32_t initialSlots = 1024,
              PoolLayout layout = PoolLayout::Texture);

  int pageSize() const { return pageSize_; }
  std::array<std::int64_t, 3> dims() const { return dims_; }
  std::array<std::int64_t, 3> pages() const { return pages_; }  // virtual pages per axis
  std::int64_t virtualPageCount() const { return pages_[0] * pages_[1] * pages_[2]; }
  std::int64_t pageIndex(std::int64_t px, std::int64_t py, std::int64_t pz) const {
    return (pz * pages_[1] + py) * pages_[0] + px;
  }
  std::array<std::int64_t, 3> pageCoords(std::int64_t page) const {
    return {page % pages_[0], (page / pages_[0]) % pages_[1], page / (pages_[0] * pages_[1])};
  }

  std::int32_t slotOf(std::int64_t page) const { return pageTable_[std::size_t(page)]; }
  const std::vector<std::int32_t>& pageTable() const { return pageTable_; }  // slot per virtual page
  bool isActive(std::int64_t page) const { return slotOf(page) > kInsideSlot; }
  std::int64_t pageOfSlot(std::int32_t slot) const { return inverseTable_[std::size_t(slot)]; }

  // Maps `page` to a free slot (growing the pool if needed) and returns it. The caller fills the
  // slot with the value of the static page it was mapped to (see staticSlot).
  std::int32_t activate(std::int64_t page);
  // Maps an active page back to the static inside or outside page and frees its slot.
  void release(std::int64_t page, bool inside);
  // For an inactive page: which static slot it maps to.
  std::int32_t staticSlot(std::int64_t page) const { return slotOf(page); }
  // Marks an inactive page as inside or outside (e.g. when a seed covers it whole).
  void setStatic(std::int64_t page, bool inside);

  // Activation hands out slots wherever they were freed, so as a band moves, neighbouring pages
  // scatter over the pool. This gives the active pages slots kInsideSlot + 1, + 2, ... in the order
  // of their virtual page index (x fastest, then y, then z) and lists them in that order: a pass over
  // the pages then reads the pool from one end to the other, each page's neighbours (a row of pages,
  // a slice of them away) a short way off. Returns the moves, {old slot, new slot}, that the backend
  // must make to its storage. The list's order can change with no move: tell the backend either way.
  std::vector<std::pair<std::int32_t, std::int32_t>> renumberInPageOrder();
  // Activations and releases since the last renumbering (or since the manager was made).
  std::int64_t changesSinceRenumbering() const { return stats_.activations + stats_.releases - renumberedAt_; }

  // Active pages, in a stable order that changes only through activate/release (swap-remove) and
  // renumberInPageOrder.
  const std::vector<std::int64_t>& activePages() const { return active_; }

  // Slots of the 3x3x3 pages around `page` (index (dz+1)*9 + (dy+1)*3 + (dx+1)); pages outside the
  // volume read as the static outside page.
  std::array<std::int32_t, 27> neighbourSlots(std::int64_t page) const;

  std::int32_t poolPagesX() const { return poolPagesX_; }
  // The capacity one growth gives a pool of `capacity` slots: whole rows, doubling (at least a row),
  // so slot origins never move. The GPU's page passes grow by the same rule.
  std::int32_t grownCapacity(std::int32_t capacity) const {
    return capacity + (capacity == 0 ? 1 : std::max<std::int32_t>(1, capacity / poolPagesX_)) * poolPagesX_;
  }
  std::int32_t capacity() const { return capacity_; }  // slots, static ones included
  std::array<std::int32_t, 2> slotOrigin(std::int32_t slot) const {
    return {(slot % poolPagesX_) * pageSize_, (slot / poolPagesX_) * pageSize_};
  }
  // Where texel (x, y) of slot `slot` (0 <= x, y < P) lies in the pool, rows of poolPagesX * P texels.
  std::size_t slotTexel(std::int32_t slot, std::int64_t x, std::int64_t y) const {
    const auto origin = slotOrigin(slot);
    return std::size_t(origin[1] + y) * std::size_t(poolPagesX_) * std::size_t(pageSize_) + std::size_t(origin[0] + x);
  }
  // Where voxel (x, y, z) lies in the pool: through the page table, so an inactive page's voxels read
  // its static slot.
  std::size_t poolTexel(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return slotTexel(slotOf(pageIndex(x / pageSize_, y / pageSize_, z)), x % pageSize_, y % pageSize_);
  }

  // The free stack, its top last (the GPU's page passes take slots from the same stack).
  const std::vector<std::int32_t>& freeSlots() const { return freeStack_; }

  struct Stats {
    std::int64_t active = 0, peakActive = 0, activations = 0, releases = 0, growths = 0, renumberings = 0;
  };
  const Stats& stats() const { return stats_; }

  // Takes the state the GPU's page passes left (levelset/gpu_page_chain.h): the page table, the active
  // list, the free stack and the pool's capacity (it only grows); `since` counts what they did since
  // this manager's state went to the GPU (activations, releases, growths; peakActive their peak).
  void adopt(std::vector<std::int32_t> pageTable, std::vector<std::int64_t> active, std::vector<std::int32_t> freeStack,
             std::int32_t capacity, const Stats& since);

private:
  void grow();
  std::array<std::int64_t, 3> dims_, pages_;
  int pageSize_;
  std::int32_t poolPagesX_, capacity_;
  std::vector<std::int32_t> pageTable_;
  std::vector<std::int64_t> inverseTable_;
  std::vector<std::int32_t> freeStack_;
  std::vector<std::int64_t> active_;
  std::vector<std::int32_t> activePosition_;  // per slot: index in active_
  Stats stats_;
  std::int64_t renumberedAt_ = 0;  // activations + releases at the last renumbering
};

}  // namespace isoatlas::levelset
