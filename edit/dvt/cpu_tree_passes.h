// CpuTreePasses: the DVT passes (tree_passes.h) on the CPU with TBB, the GPU passes' twin and oracle.
#pragma once
#include <memory>

#include "edit/dvt/tree_passes.h"

namespace isoatlas::edit::dvt {

std::unique_ptr<TreePasses> makeCpuTreePasses();

}  // namespace isoatlas::edit::dvt
