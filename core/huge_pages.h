// allocateBlock: what the global operator new of our executables does (global_new.cpp defines it;
// a program that counts its heap calls this from its own). As the standard operator new, but a block
// of 4 MiB or more is marked for transparent huge pages (madvise MADV_HUGEPAGE) before it is used.
//
// Why: the large arrays of every stage (a level set's page pool and its source volume, a mesh and
// its history, a distance tree) are read at scattered places, and with 4 KiB pages nearly every such
// read misses the TLB. Debian's kernel gives huge pages only to memory so marked ("madvise" mode).
// Only the 2 MiB-aligned interior of a block is marked, so no huge page is shared with another block
// and nothing is held beyond what the block spans. Where the kernel gives no huge pages the advice
// is ignored. Blocks come from malloc, so free() releases them.
#pragma once
#include <cstddef>

namespace isoatlas {

void* allocateBlock(std::size_t bytes);  // throws std::bad_alloc as operator new does

}  // namespace isoatlas
