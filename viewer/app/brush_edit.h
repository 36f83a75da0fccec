// brushSegmentation: a brush stroke on a segmentation through a dynamic volume tree, as `isoatlas edit`
// makes one: the level set's inside (read from its pages) written into a tree at its voxels, the brush
// applied (union or subtract), the tree collapsed. Returns the tree (the tree view shows it) and its
// mask in the level set's grid, the segmentation to go on from.
//   gpu: the context whose compute shaders run the tree passes (the window's), or null for the CPU twin
//   levels: the brush's depth past the voxels' (-3: cells of 2 x 2 x 2 voxels; past 0 the tree holds
//     detail the mask, at the voxels, does not keep)
#pragma once
#include <memory>

#include "core/gl/context.h"
#include "core/volume.h"
#include "levelset/dvt/dynamic_volume_tree.h"
#include "levelset/dvt/solid.h"
#include "levelset/level_set.h"

namespace isoatlas::viewer {

struct BrushResult {
  std::unique_ptr<levelset::dvt::DynamicVolumeTree> tree;
  Volume mask;
};

BrushResult brushSegmentation(const levelset::LevelSet& levelSet, const levelset::dvt::Solid& brush, levelset::dvt::Op op,
                              gl::Context* gpu, int levels = 0);

}  // namespace isoatlas::viewer
