// CpuSolver: the paged solver on the CPU, TBB over active pages; the GPU solver's twin and the
// backend for machines without a GPU (--backend cpu).
//   source: the volume's intensities (the speed D(I) is computed from them), read page by page as
//           pages become active and held only while they are (core/volume_source.h)
//   pageSize: the PageManager's P. Any pool layout works; PoolLayout::Contiguous is the fast one.
//   topology: Free, or Preserve (solver_backend.h)
#pragma once
#include <memory>

#include "core/volume_source.h"
#include "levelset/solver_backend.h"

namespace isoatlas::levelset {

std::unique_ptr<SolverBackend> makeCpuSolver(std::shared_ptr<const VolumeSource> source, int pageSize,
                                             Topology topology = Topology::Free);

}  // namespace isoatlas::levelset
