#include "viewer/brush_edit.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "edit/solids/rasterise.h"
#include "edit/solids/volume_solid.h"
#include "pipeline/volume_editing.h"

namespace isoatlas::viewer {

namespace dvt = edit::dvt;

BrushStroke::BrushStroke(const levelset::LevelSet& levelSet, dvt::Op op, levelset::Backend backend, int levels)
    : op_(op), preview_(levelSet.mask()) {
  const dvt::TreeFrame frame = dvt::frameOf(levelSet.geometry());
  const std::uint32_t voxels = frame.voxelDepth();
  require(levels >= -int(voxels) && int(voxels) + levels <= int(dvt::kMaxDepth), "the brush's depth is past the tree's range");
  depth_ = std::uint32_t(int(voxels) + levels);
  tree_ = pipeline::treeOfLevelSet(levelSet, {.depth = voxels}, backend).tree;  // as `isoatlas edit` makes it
}

void BrushStroke::apply(const dvt::Solid& shape) {
  require(bool(tree_), "the brush stroke has ended");
  const dvt::TreeFrame& frame = tree_->frame();
  dvt::PreOrderInput input = dvt::rasterise(shape, frame, depth_);
  std::vector<dvt::Cell> painted;  // the cells whose centres are inside the shape (value > 0)
  for (const dvt::InputVoxel& v : input.voxels())
    if (v.value > 0) painted.push_back(dvt::unpackCell(v.xy, v.zd));
  tree_->write(std::move(input), op_);  // first: a write past the node limit throws, and paints nothing
  ++dabs_;
  // Each painted cell sets the voxels it covers: inside for a union, outside for a subtraction. A
  // cell finer than a voxel paints the voxel it lies in.
  const std::uint8_t paint = op_ == dvt::Op::Union ? 1 : 0;
  for (const dvt::Cell& c : painted) {
    const Vec3 size = frame.cellVoxels(c.depth);
    const std::uint32_t at[3] = {c.x, c.y, c.z};
    std::int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::int64_t(double(at[a]) * size[a]);
      hi[a] = std::min<std::int64_t>(preview_.dims[a], std::max<std::int64_t>(lo[a] + 1, std::int64_t(double(at[a] + 1) * size[a])));
    }
    for (std::int64_t k = lo[2]; k < hi[2]; ++k)
      for (std::int64_t j = lo[1]; j < hi[1]; ++j)
        for (std::int64_t i = lo[0]; i < hi[0]; ++i) preview_.setValue(preview_.index(i, j, k), paint);
  }
}

void BrushStroke::dabTo(const Vec3& centre, double radius) {
  apply(*kept(last_ ? dvt::capsuleBrush(*last_, centre, radius) : dvt::sphereBrush(centre, radius)));
  last_ = centre;
}

void BrushStroke::keepToSlice(int axis, const Vec3& through) {
  require(axis >= 0 && axis < 3, "a slice is normal to voxel axis 0, 1 or 2");
  Vec3 index = preview_.worldToIndex(through);
  index[axis] = std::round(index[axis]);  // the plane through voxel centres: exactly their layer
  // The slice's plane is spanned by the other two voxel axes; half the layer's thickness either side.
  const Vec3 origin = preview_.indexToWorld(index);
  const auto along = [&](int a) {
    Vec3 step{0, 0, 0};
    step[a] = 1;
    return preview_.indexToWorld(index + step) - origin;
  };
  const Vec3 normal = unit(cross(along((axis + 1) % 3), along((axis + 2) % 3)));
  slice_ = Slice{origin, normal, 0.5 * std::abs(dot(along(axis), normal))};
}

std::unique_ptr<dvt::DistanceSolid> BrushStroke::kept(std::unique_ptr<dvt::DistanceSolid> shape) const {
  if (!slice_) return shape;
  return dvt::withinSlab(std::move(shape), slice_->point, slice_->normal, slice_->halfWidth);
}

BrushResult BrushStroke::finish() {
  require(bool(tree_), "the brush stroke has ended");
  tree_->collapse();
  BrushResult r;
  r.mask = dvt::sampleMask(tree_->tree(), preview_.dims);
  r.tree = std::move(tree_);
  return r;
}

BrushResult brushSegmentation(const levelset::LevelSet& levelSet, const dvt::Solid& brush, dvt::Op op, levelset::Backend backend,
                              int levels) {
  BrushStroke stroke(levelSet, op, backend, levels);
  stroke.apply(brush);
  return stroke.finish();
}

}  // namespace isoatlas::viewer
