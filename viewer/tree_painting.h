// TreePainting: a sphere brush dragged over a volume tree (the window's tree view, `isoatlas view
// TREE.dvt`), as BrushStroke drags one over a segmentation. Each dab is one write of a sphere, swept
// as a capsule from the stroke's last dab so that fast moves leave no gaps, into a DynamicVolumeTree
// on the window's backend; the picture is drawn from the tree the write leaves: on the GPU straight
// from the tree passes' buffers (nothing crosses to the host between the dab and its picture), on the
// CPU from its streams, uploaded after each dab.
//   TreePainting  tree: where the painting starts; backend: the tree passes' (Gpu: compute shaders in
//                 the current context, which must stay current); options: the node limit
//   dabTo         one dab of `radius` (world units) at `centre`, union (add) or subtraction; a dab past
//                 the node limit throws Error with the tree changed where it needed no new nodes
//                 (dynamic_volume_tree.h), and buffers() then hold that tree
//   endStroke     the stroke's tree collapsed (one edit); the next dab starts a new sweep
//   buffers, nodeCount, frame   what render::DvtRenderer::draw takes, valid until the next dab
//   tree          the tree as it is now (the GPU's read back)
//   pickTree      where a ray first enters the inside of a tree (marched in half voxels; for a mouse
//                 click, not for many rays)
#pragma once
#include <memory>
#include <optional>

#include "core/gl/resources.h"
#include "edit/dvt/dynamic_volume_tree.h"
#include "edit/dvt/gpu_tree_passes.h"
#include "levelset/backend.h"

namespace isoatlas::viewer {

class TreePainting {
public:
  TreePainting(const edit::dvt::VolumeTree& tree, levelset::Backend backend, const edit::dvt::TreeOptions& options = {});
  void dabTo(const Vec3& centre, double radius, bool add);
  void endStroke();
  std::size_t dabs() const { return dabs_; }
  edit::dvt::GpuTreeBuffers buffers() const;
  std::uint64_t nodeCount() const { return tree_->nodeCount(); }
  const edit::dvt::TreeFrame& frame() const { return tree_->frame(); }
  edit::dvt::VolumeTree tree() const { return tree_->tree(); }
  std::string backend() const { return tree_->backend(); }

private:
  void upload();  // the CPU's streams to buffers the renderer reads
  std::unique_ptr<edit::dvt::DynamicVolumeTree> tree_;
  std::unique_ptr<gl::Buffer> pointers_, cells_;  // the CPU's, uploaded
  std::optional<Vec3> last_;
  std::size_t dabs_ = 0;
};

std::optional<Vec3> pickTree(const edit::dvt::VolumeTree& tree, const Vec3& origin, const Vec3& direction);

}  // namespace isoatlas::viewer
