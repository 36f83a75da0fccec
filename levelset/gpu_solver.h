// GpuSolver: the paged solver in GL 4.5 compute shaders (levelset/shaders/). phi lives in two r32f
// pool textures (ping-pong) laid out exactly as PageManager says; the source's intensities sit in a
// third pool texture, page for page beside phi's, written when a page takes a slot (read from the
// source then: core/volume_source.h), so GPU memory follows the active pages and not the volume (a
// run that manages its pages on the GPU, gpu_page_chain.h, holds the whole source there instead). The speed reads them, so changing T/eps/alpha costs
// nothing. Per iteration the CPU uploads the active-page table when the active set changed and reads
// back one byte per active page plus 16 bytes of counters.
// Runs in the GL context current when it is made (gl::Context::current(), checked); that context
// must be current whenever the solver is used or destroyed.
#pragma once
#include <memory>

#include "core/volume_source.h"
#include "levelset/solver_backend.h"

namespace isoatlas::levelset {

std::unique_ptr<SolverBackend> makeGpuSolver(std::shared_ptr<const VolumeSource> source, Topology topology = Topology::Free);

}  // namespace isoatlas::levelset
