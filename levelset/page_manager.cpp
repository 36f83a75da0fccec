#include "levelset/page_manager.h"

#include <algorithm>

#include "core/error.h"

namespace isoatlas::levelset {

PageManager::PageManager(std::array<std::int64_t, 3> dims, int pageSize, std::int32_t initialSlots, PoolLayout layout)
    : dims_(dims), pageSize_(pageSize) {
  require(isPageSize(pageSize),
          "page size " + std::to_string(pageSize) + " must be a power of two from 4 to " + std::to_string(kMaxPageSize));
  for (int a = 0; a < 2; ++a) pages_[a] = (dims[a] + pageSize - 1) / pageSize;
  pages_[2] = dims[2];
  // Rows of slots are appended as the pool grows.
  poolPagesX_ = layout == PoolLayout::Texture ? textureSlotsPerRow(pageSize) : 1;
  capacity_ = 0;
  pageTable_.assign(std::size_t(virtualPageCount()), kOutsideSlot);
  initialSlots = std::max(initialSlots, poolPagesX_);
  while (capacity_ < initialSlots) grow();
  stats_.growths = 0;  // count only the growth that running out of slots causes
}

void PageManager::grow() {
  const std::int32_t old = capacity_;
  capacity_ = grownCapacity(capacity_);
  inverseTable_.resize(std::size_t(capacity_), -1);
  activePosition_.resize(std::size_t(capacity_), -1);
  // Pushed in reverse so low slots are used first; slots 0 and 1 stay static.
  for (std::int32_t s = capacity_ - 1; s >= std::max(old, kInsideSlot + 1); --s) freeStack_.push_back(s);
  if (old > 0) ++stats_.growths;
}

std::int32_t PageManager::activate(std::int64_t page) {
  if (isActive(page)) return slotOf(page);
  if (freeStack_.empty()) grow();
  const std::int32_t slot = freeStack_.back();
  freeStack_.pop_back();
  pageTable_[std::size_t(page)] = slot;
  inverseTable_[std::size_t(slot)] = page;
  activePosition_[std::size_t(slot)] = std::int32_t(active_.size());
  active_.push_back(page);
  ++stats_.activations;
  stats_.active = std::int64_t(active_.size());
  stats_.peakActive = std::max(stats_.peakActive, stats_.active);
  return slot;
}

void PageManager::release(std::int64_t page, bool inside) {
  const std::int32_t slot = slotOf(page);
  if (slot <= kInsideSlot) return;
  const std::int32_t at = activePosition_[std::size_t(slot)];
  const std::int64_t last = active_.back();
  active_[std::size_t(at)] = last;
  activePosition_[std::size_t(slotOf(last))] = at;
  active_.pop_back();
  activePosition_[std::size_t(slot)] = -1;
  inverseTable_[std::size_t(slot)] = -1;
  freeStack_.push_back(slot);
  pageTable_[std::size_t(page)] = inside ? kInsideSlot : kOutsideSlot;
  ++stats_.releases;
  stats_.active = std::int64_t(active_.size());
}

std::vector<std::pair<std::int32_t, std::int32_t>> PageManager::renumberInPageOrder() {
  renumberedAt_ = stats_.activations + stats_.releases;
  ++stats_.renumberings;
  std::sort(active_.begin(), active_.end());
  std::vector<std::pair<std::int32_t, std::int32_t>> moves;
  std::fill(inverseTable_.begin(), inverseTable_.end(), -1);
  std::fill(activePosition_.begin(), activePosition_.end(), -1);
  for (std::size_t k = 0; k < active_.size(); ++k) {
    const std::int64_t page = active_[k];
    const std::int32_t to = kInsideSlot + 1 + std::int32_t(k), from = slotOf(page);
    if (from != to) moves.push_back({from, to});
    pageTable_[std::size_t(page)] = to;
    inverseTable_[std::size_t(to)] = page;
    activePosition_[std::size_t(to)] = std::int32_t(k);
  }
  freeStack_.clear();  // the slots past the active ones, low ones first, as grow() stacks them
  for (std::int32_t s = capacity_ - 1; s > kInsideSlot + std::int32_t(active_.size()); --s) freeStack_.push_back(s);
  return moves;
}

void PageManager::adopt(std::vector<std::int32_t> pageTable, std::vector<std::int64_t> active, std::vector<std::int32_t> freeStack,
                        std::int32_t capacity, const Stats& since) {
  require(pageTable.size() == pageTable_.size() && capacity >= capacity_ && capacity % poolPagesX_ == 0,
          "the GPU's page state does not fit the page manager");
  pageTable_ = std::move(pageTable);
  active_ = std::move(active);
  freeStack_ = std::move(freeStack);
  capacity_ = capacity;
  inverseTable_.assign(std::size_t(capacity_), -1);
  activePosition_.assign(std::size_t(capacity_), -1);
  for (std::size_t k = 0; k < active_.size(); ++k) {
    const std::int32_t slot = slotOf(active_[k]);
    require(slot > kInsideSlot && slot < capacity_ && inverseTable_[std::size_t(slot)] < 0,
            "the GPU's page state gives two active pages one slot, or a static one");
    inverseTable_[std::size_t(slot)] = active_[k];
    activePosition_[std::size_t(slot)] = std::int32_t(k);
  }
  require(active_.size() + freeStack_.size() + 2 == std::size_t(capacity_), "the GPU's page state lost slots");
  stats_.activations += since.activations;
  stats_.releases += since.releases;
  stats_.growths += since.growths;
  stats_.active = std::int64_t(active_.size());
  stats_.peakActive = std::max(stats_.peakActive, since.peakActive);
}

void PageManager::setStatic(std::int64_t page, bool inside) {
  if (!isActive(page)) pageTable_[std::size_t(page)] = inside ? kInsideSlot : kOutsideSlot;
}

std::array<std::int32_t, 27> PageManager::neighbourSlots(std::int64_t page) const {
  const auto [px, py, pz] = pageCoords(page);
  std::array<std::int32_t, 27> out{};
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const std::int64_t x = px + dx, y = py + dy, z = pz + dz;
        const bool inside = x >= 0 && y >= 0 && z >= 0 && x < pages_[0] && y < pages_[1] && z < pages_[2];
        out[std::size_t((dz + 1) * 9 + (dy + 1) * 3 + (dx + 1))] = inside ? slotOf(pageIndex(x, y, z)) : kOutsideSlot;
      }
  return out;
}

}  // namespace isoatlas::levelset
