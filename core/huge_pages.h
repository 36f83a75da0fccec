// HugePageVector: a std::vector for the large arrays that are read at scattered places (a level
// set's page pool and its source volume, the simplifier's history). A block of 4 MiB or more is
// marked for transparent huge pages (madvise MADV_HUGEPAGE) before it is used, so that a few TLB
// entries cover it where 4 KiB pages would need one per read; Debian's kernel gives huge pages only
// to memory so marked ("madvise" mode). Only the 2 MiB-aligned interior of a block is marked, so no
// huge page is shared with another block. Where the kernel gives no huge pages the advice is ignored.
//
// Not for every allocation: a huge page costs its whole 2 MiB to clear when first touched, which
// pays only for arrays that are read many times over (making every block of the demo's process so
// cost more in clearing than it gained).
#pragma once
#include <cstddef>
#include <cstdlib>
#include <vector>

namespace isoatlas {

// As operator new (std::bad_alloc when out of memory), marking blocks of 4 MiB or more; std::free
// releases the block.
void* allocateForHugePages(std::size_t bytes);

template <class T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) { return static_cast<T*>(allocateForHugePages(n * sizeof(T))); }
  void deallocate(T* block, std::size_t) noexcept { std::free(block); }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const noexcept {
    return true;
  }
};

template <class T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace isoatlas
