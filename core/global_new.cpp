// The global operator new and delete of our executables and the Python module, linked into each
// (the isoatlas_global_new object library; not into the sanitizer builds, which bring their own).
// allocateBlock says what they add to the standard ones.
#include <cstdlib>
#include <new>

#include "core/huge_pages.h"

void* operator new(std::size_t bytes) { return isoatlas::allocateBlock(bytes); }
void* operator new[](std::size_t bytes) { return isoatlas::allocateBlock(bytes); }
void operator delete(void* block) noexcept { std::free(block); }
void operator delete[](void* block) noexcept { std::free(block); }
void operator delete(void* block, std::size_t) noexcept { std::free(block); }
void operator delete[](void* block, std::size_t) noexcept { std::free(block); }
