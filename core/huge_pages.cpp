#include "core/huge_pages.h"

#include <sys/mman.h>

#include <cstdint>
#include <new>

namespace isoatlas {
namespace {

constexpr std::size_t kHugePage = std::size_t(2) << 20;
constexpr std::size_t kAdvisedFrom = 2 * kHugePage;

}  // namespace

void adviseHugePages(void* block, std::size_t bytes) {
  if (bytes < kAdvisedFrom) return;
  const std::uintptr_t begin = (std::uintptr_t(block) + kHugePage - 1) & ~(kHugePage - 1);
  const std::uintptr_t end = (std::uintptr_t(block) + bytes) & ~(kHugePage - 1);
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);  // advice only
}

void* allocateForHugePages(std::size_t bytes) {
  void* block = std::malloc(bytes ? bytes : 1);
  if (!block) throw std::bad_alloc();
  adviseHugePages(block, bytes);
  return block;
}

}  // namespace isoatlas
