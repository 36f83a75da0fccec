// HugePageVector: a std::vector for the large arrays that are read at scattered places (a level
// set's page pool and its source volume, the simplifier's history). A block of 4 MiB or more is
// marked for transparent huge pages (madvise MADV_HUGEPAGE) before it is used, so that a few TLB
// entries cover it where 4 KiB pages would need one per read; Debian's kernel gives huge pages only
// to memory so marked ("madvise" mode). Only the 2 MiB-aligned interior of a block is marked, so no
// huge page is shared with another block while it lives. Where the kernel gives no huge pages the
// advice is ignored.
//
// Not for every allocation: a huge page costs its whole 2 MiB to clear when first touched, which
// pays only for arrays that are read many times over, or written whole (one fault fills 2 MiB where
// 512 would), and not for blocks touched here and there (making every block of the demo's process
// so cost more in clearing than it gained).
#pragma once
#include <cstddef>
#include <cstdlib>
#include <limits>
#include <memory>
#include <new>
#include <type_traits>
#include <vector>

namespace isoatlas {

// As operator new (std::bad_alloc when out of memory), marking blocks of 4 MiB or more; std::free
// releases the block.
void* allocateForHugePages(std::size_t bytes);

// Marks the 2 MiB-aligned interior of a block of 4 MiB or more for huge pages (advice only).
void adviseHugePages(void* block, std::size_t bytes);

// Reserves room for n elements in a std::vector and marks the block as allocateForHugePages does, for
// a large array that is then written whole (a mesh being extracted): every page of it is cleared
// either way, and huge pages take 512 times fewer faults to fill it. Elements it already holds are
// copied first, so their pages stay small.
template <class T, class Allocator>
void reserveForHugePages(std::vector<T, Allocator>& v, std::size_t n) {
  v.reserve(n);
  adviseHugePages(v.data(), n * sizeof(T));
}

// Releases a block of allocateForHugePages.
struct FreeBlock {
  void operator()(void* block) const noexcept { std::free(block); }
};
template <class T>
using HugePageArray = std::unique_ptr<T[], FreeBlock>;

// An array of n T left uninitialised, for trivial types whose every element is written before it is
// read; its block marked as allocateForHugePages does (when 4 MiB or more).
template <class T>
HugePageArray<T> makeHugePageArray(std::size_t n) {
  static_assert(std::is_trivially_default_constructible_v<T> && std::is_trivially_destructible_v<T>);
  static_assert(alignof(T) <= alignof(std::max_align_t), "malloc's alignment");
  if (n > std::numeric_limits<std::size_t>::max() / sizeof(T)) throw std::bad_array_new_length();
  return HugePageArray<T>(static_cast<T*>(allocateForHugePages(n * sizeof(T))));
}

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
