// Pictures of a dynamic volume tree (edit/dvt), drawn in the current GL context straight from the
// tree's pointer and node streams (Keller et al., sec. 5.1):
//   Cubes:   one instanced cube per inside leaf (the vertex stage drops every other node), flat shaded.
//   RayCast: a ray per pixel walks the tree from leaf to leaf (coarse empty leaves are skipped whole)
//            to the first zero of the sub-voxel distances interpolated between the leaves, and is
//            lit from their gradient there.
// DvtRenderer draws buffers a GPU tree already has (gpuTreeBuffers) or uploads a CPU tree's streams.
#pragma once
#include <memory>

#include "core/gl/context.h"
#include "core/gl/resources.h"
#include "core/image.h"
#include "edit/dvt/gpu_tree_passes.h"
#include "edit/dvt/volume_tree.h"
#include "render/camera.h"

namespace isoatlas::render {

enum class DvtRenderMode { Cubes, RayCast };

struct DvtView {
  Camera camera;
  DvtRenderMode mode = DvtRenderMode::RayCast;
  Vec3 colour{0.93, 0.78, 0.62}, background{1, 1, 1};
};

class DvtRenderer {
public:
  DvtRenderer();  // in gl::Context::current(), as every renderer of render/
  // Draws into the bound framebuffer (of the camera's size).
  void draw(const edit::dvt::GpuTreeBuffers& buffers, std::uint64_t nodeCount, const edit::dvt::TreeFrame& frame,
            const DvtView& view);

private:
  const gl::Program &cubes_, &rayCast_;
  gl::VertexArray vao_;
  std::unique_ptr<gl::Framebuffer> rays_;  // the ray caster's picture, at the last camera's size
};

// The world box of the tree's inside leaves (the whole box when there are none).
Box insideBounds(const edit::dvt::VolumeTree& tree);
// A picture of a tree, drawn offscreen in the current context and read back (rows top to bottom):
// from a GPU tree's buffers, or a CPU tree's streams uploaded.
Image renderTree(const edit::dvt::GpuTreeBuffers& buffers, std::uint64_t nodeCount, const edit::dvt::TreeFrame& frame,
                 const DvtView& view);
Image renderTree(const edit::dvt::VolumeTree& tree, const DvtView& view);

}  // namespace isoatlas::render
