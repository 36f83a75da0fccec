// CpuTreePasses: the DVT passes (tree_passes.h) on the CPU with TBB, the GPU passes' twin and oracle.
#pragma once
#include <memory>

#include "levelset/dvt/tree_passes.h"

namespace isoatlas::levelset::dvt {

std::unique_ptr<TreePasses> makeCpuTreePasses();

}  // namespace isoatlas::levelset::dvt
