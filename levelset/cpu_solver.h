// CpuSolver: the paged solver on the CPU, TBB over active pages; the GPU solver's twin and the
// backend for machines without a GPU (--backend cpu).
//   source: the volume's intensities as floats, x fastest (the speed D(I) is computed from them)
//   pageSize: the PageManager's P. Any pool layout works; PoolLayout::Contiguous is the fast one.
//   topology: Free, or Preserve (solver_backend.h)
#pragma once
#include <memory>

#include "levelset/solver_backend.h"

namespace isoatlas::levelset {

std::unique_ptr<SolverBackend> makeCpuSolver(const std::vector<float>& source, std::array<std::int64_t, 3> dims, int pageSize,
                                             Topology topology = Topology::Free);

}  // namespace isoatlas::levelset
