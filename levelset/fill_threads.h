// fillThreads: the background threads a topology-preserving segmentation leaves inside its object,
// filled without changing its topology. Where the free front would leave a cavity (around a voxel
// of noise the data term pushes out), the preserved one cannot, so the cavity stays joined to the
// outside by a thread of background a voxel wide: a dent no model of the surface can follow. The
// free front's cavities are dropped with the small components; these are filled instead. A
// background voxel with at most kThreadNeighbours background voxels among its 26 neighbours is taken
// in where it is a simple point (levelset/simple_point.h), from the threads' ends inwards, until
// none is left: a thread that ends inside is filled up to the surface; a tunnel through the object,
// or a sulcus's sheet, is not.
// Input and output: mask, uint8, 1 inside. Returns the voxels taken in. Past the volume's edge is outside.
#pragma once
#include <cstdint>

#include "core/volume.h"

namespace isoatlas::levelset {

inline constexpr int kThreadNeighbours = 2;

std::int64_t fillThreads(Volume& mask);

}  // namespace isoatlas::levelset
