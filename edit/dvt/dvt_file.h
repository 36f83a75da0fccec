// The .dvt file, version 1: a volume tree (volume_tree.h) as `isoatlas edit` saves it. The layout of
// core/sectioned_file.h (magic "ISOA-DVT"), little-endian, integers unsigned unless said:
//   FRAM  voxel splits K (u32, at most 16), spacing (f64 x 3, > 0), origin (f64 x 3), direction
//         (f64 x 9, row-major), all finite
//   GRID  optional, after FRAM: the source volume's voxels along x, y, z (u64 x 3, each 1 .. 2^K),
//         the grid a mask of the tree comes back on; without it (files of older isoatlas, trees of
//         meshes) the whole box, 2^K a side. Written when the frame has an extent.
//   NODE  node count (u64, >= 1), then per node in pre-order: parent, left, right (i32 x 3; -1 none),
//         value (f32), cell (u32 x 2: x | y << 16, z | depth << 16)
// FRAM and NODE once each, FRAM first. The reader checks every count against the section before it
// allocates and the tree itself (treeProblem) before it returns; unknown sections are skipped.
#pragma once
#include <string>

#include "edit/dvt/volume_tree.h"

namespace isoatlas::edit::dvt {

inline constexpr std::uint32_t kDvtVersion = 1;

void writeDvt(const std::string& path, const VolumeTree& tree);
VolumeTree readDvt(const std::string& path, bool checksums = true);  // false only for fuzzing

}  // namespace isoatlas::edit::dvt
