// core/huge_pages.h: a large HugePageVector, a vector reserved with reserveForHugePages and a
// HugePageArray lie in memory marked for transparent huge pages (their mapping's VmFlags say "hg")
// and hold what is written to them; a block under 4 MiB is not marked.
#include "core/huge_pages.h"

#include <gtest/gtest.h>
#include <sys/mman.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace isoatlas {
namespace {

// The VmFlags of the mapping holding `address`, from /proc/self/smaps ("" if none holds it).
std::string vmFlagsAt(const void* address) {
  std::ifstream smaps("/proc/self/smaps");
  const auto a = std::uintptr_t(address);
  bool inside = false;
  for (std::string line; std::getline(smaps, line);) {
    std::uintptr_t begin = 0, end = 0;
    char dash = 0;
    std::istringstream range(line);
    if (range >> std::hex >> begin >> dash >> end && dash == '-' && line.find(':') > line.find(' ')) {
      inside = begin <= a && a < end;  // a mapping's first line: its address range
      continue;
    }
    if (inside && line.starts_with("VmFlags:")) return line.substr(8);
  }
  return "";
}

bool advised(const std::string& flags) { return (" " + flags + " ").find(" hg ") != std::string::npos; }

TEST(HugePages, ALargeVectorIsMarkedForHugePagesAndHoldsItsValues) {
  if (!std::filesystem::exists("/sys/kernel/mm/transparent_hugepage/enabled"))
    GTEST_SKIP() << "this kernel has no transparent huge pages";
  constexpr std::size_t kCount = std::size_t(16) << 20;  // 64 MiB of floats
  HugePageVector<float> large(kCount);
  for (std::size_t i = 0; i < kCount; i += 4096) large[i] = float(i);
  const float* middle = large.data() + kCount / 2;
  EXPECT_TRUE(advised(vmFlagsAt(middle))) << "VmFlags:" << vmFlagsAt(middle);
  for (std::size_t i = 0; i < kCount; i += 4096) ASSERT_EQ(large[i], float(i));

  HugePageVector<std::uint8_t> grown;  // reallocated as it grows: each block marked
  for (std::size_t i = 0; i < (std::size_t(8) << 20); ++i) grown.push_back(std::uint8_t(i));
  EXPECT_TRUE(advised(vmFlagsAt(grown.data() + grown.size() / 2)));
  EXPECT_EQ(grown[12345], std::uint8_t(12345));
}

TEST(HugePages, AReservedVectorAndAnArrayAreMarkedForHugePages) {
  if (!std::filesystem::exists("/sys/kernel/mm/transparent_hugepage/enabled"))
    GTEST_SKIP() << "this kernel has no transparent huge pages";
  // 64 MiB of each: past glibc's largest threshold (32 MiB) a block is always a mapping of its own, so
  // no earlier block's advice can lie under it and only the call under test can mark it.
  constexpr std::size_t kCount = std::size_t(16) << 20;
  std::vector<std::uint32_t> reserved;
  reserveForHugePages(reserved, kCount);
  reserved.resize(kCount, 7u);
  EXPECT_TRUE(advised(vmFlagsAt(reserved.data() + kCount / 2)));
  EXPECT_EQ(reserved[kCount - 1], 7u);

  const HugePageArray<float> array = makeHugePageArray<float>(kCount);
  for (std::size_t i = 0; i < kCount; ++i) array[i] = float(i);
  EXPECT_TRUE(advised(vmFlagsAt(array.get() + kCount / 2)));
  EXPECT_EQ(array[kCount - 1], float(kCount - 1));
}

TEST(HugePages, ABlockUnder4MiBIsLeftAsItIs) {
  // A mapping of its own, so no earlier block's advice can lie under it (malloc's heap may reuse one).
  constexpr std::size_t kMapped = std::size_t(8) << 20;
  void* mapped = mmap(nullptr, kMapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(mapped, MAP_FAILED);
  auto* bytes = static_cast<std::uint8_t*>(mapped);
  // 3 MiB from a 2 MiB boundary: a huge page's worth of interior, which only the size keeps unmarked.
  constexpr std::uintptr_t kHugePage = std::uintptr_t(2) << 20;
  auto* aligned = reinterpret_cast<std::uint8_t*>((reinterpret_cast<std::uintptr_t>(bytes) + kHugePage - 1) & ~(kHugePage - 1));
  adviseHugePages(aligned, std::size_t(3) << 20);
  EXPECT_FALSE(advised(vmFlagsAt(aligned + (std::size_t(1) << 20))));
  adviseHugePages(bytes, kMapped);  // the same block, 8 MiB: its aligned interior is marked
  EXPECT_TRUE(advised(vmFlagsAt(bytes + kMapped / 2)));
  munmap(mapped, kMapped);
}

}  // namespace
}  // namespace isoatlas
