// Brush edits of a segmentation through a dynamic volume tree, as `isoatlas edit` makes them: the
// level set's inside (read from its pages) written into a tree at its voxels, the brush applied
// (union or subtract), the tree collapsed, and its mask in the level set's grid the segmentation to
// go on from.
//   BrushStroke: a brush dragged as ITK-SNAP's paintbrush is: the tree is made once when the stroke
//   starts, each dab is one write (a sphere brush sweeps a capsule from the last dab, so fast moves
//   leave no gaps), and the mask comes from the tree when it ends. While it lasts, preview() is the
//   segmentation's mask with the dabs painted from the written cells: what the tree's mask will be,
//   exactly, for brushes at the voxels' depth (levels 0); coarser or finer brushes preview at the
//   voxels their cells cover.
//   brushSegmentation: a stroke of one shape.
//   backend: the tree passes' (Gpu: compute shaders in the current context, the window's)
//   levels: the brush's depth past the voxels' (-3: cells of 2 x 2 x 2 voxels; past 0 the tree holds
//     detail the mask, at the voxels, does not keep)
#pragma once
#include <memory>
#include <optional>

#include "core/volume.h"
#include "edit/dvt/dynamic_volume_tree.h"
#include "edit/solids/solid.h"
#include "levelset/level_set.h"

namespace isoatlas::viewer {

struct BrushResult {
  std::unique_ptr<edit::dvt::DynamicVolumeTree> tree;
  Volume mask;
};

class BrushStroke {
public:
  BrushStroke(const levelset::LevelSet& levelSet, edit::dvt::Op op, levelset::Backend backend, int levels = 0);
  // One write of `shape`, painted into the preview.
  void apply(const edit::dvt::Solid& shape);
  // A sphere of `radius` mm at `centre`, swept from the last dab's centre when there was one.
  void dabTo(const Vec3& centre, double radius);
  // From here on the dabs keep to one layer of voxels: the slice normal to voxel axis `axis` (0 i,
  // 1 j, 2 k) through the voxel nearest `through` (ITK-SNAP's 2D brush).
  void keepToSlice(int axis, const Vec3& through);
  // `shape` as the stroke paints it: cut to its slice when it keeps to one.
  std::unique_ptr<edit::dvt::DistanceSolid> kept(std::unique_ptr<edit::dvt::DistanceSolid> shape) const;
  std::size_t dabs() const { return dabs_; }
  const Volume& preview() const { return preview_; }
  // Collapses the tree and takes its mask; the stroke is spent.
  BrushResult finish();

private:
  struct Slice {
    Vec3 point, normal;
    double halfWidth;
  };
  std::optional<Slice> slice_;
  edit::dvt::Op op_;
  std::uint32_t depth_;
  std::unique_ptr<edit::dvt::DynamicVolumeTree> tree_;
  Volume preview_;  // also the segmentation's grid: its dims, spacing and placement
  std::optional<Vec3> last_;
  std::size_t dabs_ = 0;
};

BrushResult brushSegmentation(const levelset::LevelSet& levelSet, const edit::dvt::Solid& brush, edit::dvt::Op op,
                              levelset::Backend backend, int levels = 0);

}  // namespace isoatlas::viewer
