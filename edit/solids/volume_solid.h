// Segmentations as DVT solids and frames, and trees back as volumes.
//   frameOf(volume): the volume's own grid, 2^K voxels along each axis (K: the smallest that holds
//   its largest dimension), so depth 3K cells are its voxels. frameAround: an isotropic grid around a
//   world box, for inputs with no voxels (meshes).
//   VolumeSolid: a mask (an integer volume, inside where nonzero) or a phi volume (floating point,
//   inside where > 0, as isoatlas segment --phi writes it), or a level set's phi read from its pages
//   where its backend keeps them (no dense phi); trilinear between voxel centres and outside past the
//   volume's edges; cells are classified from the voxels their interpolation reads (a summed-volume
//   table of the inside voxels). A crossed cell of phi holds phi's distance to first order, phi over
//   the length of its gradient: the level set's phi is far steeper than a distance at its front (its
//   rescaling term vanishes there), so its own values would put the tree's surface on the voxels' faces.
//   sampleMask / sampleField: the tree at voxel centres (a point on a split plane belongs to the
//   upper half): a mask (uint8, 1 inside) with the frame's geometry over `dims` (default the frame's
//   grid(): the source volume's voxels), or the inside-ness in world units (leaf value times its
//   radius; > 0 inside) on the grid of the depth-d cells (fieldGrid), for extract/ to mesh at iso 0.
//   Both throw Error before allocating a volume past core's size limit.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/volume.h"
#include "edit/solids/solid.h"

namespace isoatlas::levelset {
class LevelSet;
}

namespace isoatlas::edit::dvt {

TreeFrame frameOf(const Volume& volume);
TreeFrame frameAround(const Vec3& lo, const Vec3& hi, int voxelSplits);

class VolumeSolid final : public Solid {
public:
  // The source must stay alive; frames for it come from frameOf(volume) or frameOf(levelSet.geometry()).
  explicit VolumeSolid(const Volume& volume);
  explicit VolumeSolid(const levelset::LevelSet& levelSet);
  CellClass classify(const TreeFrame& frame, const Cell& cell, double radius) const override;
  float value(const TreeFrame& frame, const Cell& cell, double radius) const override;

private:
  double field(const Vec3& index) const;  // inside-ness, trilinear; mask: +-1, phi: as the source's
  double distance(const Vec3& index, double f) const;  // phi's world distance to first order, f = field(index)
  double voxelField(std::int64_t i, std::int64_t j, std::int64_t k) const;
  std::uint64_t insideIn(const std::array<std::int64_t, 3>& lo, const std::array<std::int64_t, 3>& hi) const;
  void buildTable();
  std::array<std::int64_t, 3> dims_;
  std::function<double(std::int64_t, std::int64_t, std::int64_t)> voxel_;  // the source's value
  bool mask_;
  Vec3 spacing_;
  std::vector<std::uint32_t> table_;  // (nx+1)(ny+1)(nz+1) counts of inside voxels below each corner
};

struct LeafSample {
  float value = kOutside;
  std::uint32_t depth = 0;
};
LeafSample sampleAt(const VolumeTree& tree, const Vec3& index);
Volume sampleMask(const VolumeTree& tree, const std::array<std::int64_t, 3>& dims);
Volume sampleMask(const VolumeTree& tree);
std::array<std::int64_t, 3> fieldGrid(std::uint32_t depth);
Volume sampleField(const VolumeTree& tree, std::uint32_t depth);

}  // namespace isoatlas::edit::dvt
