// The memory budget: the most bytes one input may take once read, checked from its header before
// anything is allocated (a volume's voxels, a model's inflated charts), so a small file cannot ask for
// more memory than the machine has. Default: half the physical memory; `isoatlas --max-memory` (and
// Python's isoatlas.set_max_memory) set it; the fuzz targets lower it.
#pragma once
#include <cstdint>
#include <string>

namespace isoatlas {

std::uint64_t memoryBudget();
void setMemoryBudget(std::uint64_t bytes);

// Throws Error (BadInput) when `bytes` pass the budget: "WHAT would take N MiB, more than the memory
// budget of M GiB (--max-memory)".
void requireWithinMemoryBudget(std::uint64_t bytes, const std::string& what);

// "8G", "512M", "64K" (powers of 1024) or a plain count of bytes; throws Error (BadInput) otherwise.
std::uint64_t parseByteSize(const std::string& text);

}  // namespace isoatlas
