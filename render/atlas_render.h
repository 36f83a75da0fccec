// Rendering a model's atlas with GL 4.5 tessellation (the paper's section 4.4): the CPU's patch list
// (gpu_patches.h) drawn as quad patches, refined on the GPU with a fixed number of halvings or to a
// length on the screen, every vertex read from the position and normal atlases.
//   AtlasTextures  one model's atlas on the GPU (made once)
//   PatchBuffer    one patch list on the GPU; update() sends only the span that changed
//   AtlasRenderer  draws items (an atlas, a patch list, a placement) into a framebuffer, or captures
//                  the triangles it makes (transform feedback) in world coordinates
// All take the current GL context (gl::Context::current(), checked) and never make one.
#pragma once
#include <array>
#include <functional>
#include <vector>

#include "atlas/atlas.h"
#include "core/gl/program.h"
#include "core/gl/resources.h"
#include "core/mesh.h"
#include "render/camera.h"
#include "render/gpu_patches.h"

namespace isoatlas::render {

// The charts, and the detail charts packed alike into a second pair of textures with, per chart,
// its detail chart's slot (-1: none).
class AtlasTextures {
public:
  // Throws Error(BadInput) when the atlas is larger than the driver's largest texture.
  explicit AtlasTextures(const atlas::Atlas& atlas);
  const atlas::AtlasLayout& layout() const { return layout_; }
  const atlas::AtlasLayout& detailLayout() const { return detailLayout_; }  // charts 0 without detail
  const gl::Texture& positions() const { return positions_; }
  const gl::Texture& normals() const { return normals_; }
  const gl::Texture& detailPositions() const { return detailPositions_; }
  const gl::Texture& detailNormals() const { return detailNormals_; }
  const gl::Buffer& detailSlots() const { return detailSlots_; }

private:
  atlas::AtlasLayout layout_, detailLayout_;
  gl::Texture positions_, normals_, detailPositions_, detailNormals_;
  gl::Buffer detailSlots_;
};

class PatchBuffer {
public:
  // Replaces the list: sends the span from the first patch that differs to the last (to the end
  // when the length changed), or everything when the buffer must grow. Returns the bytes sent.
  std::size_t update(const std::vector<GpuPatch>& patches);
  std::size_t count() const { return held_.size(); }
  const gl::Buffer& buffer() const { return buffer_; }

private:
  gl::Buffer buffer_;
  std::vector<GpuPatch> held_;
};

struct DrawItem {
  const AtlasTextures* atlas;
  const PatchBuffer* patches;
  Vec3 offset{0, 0, 0};  // where the model is placed (grid scenes)
};

// The GPU stage of the cascade: `halvings` more halvings of every CPU edge (mode Level), or segments
// of about `pixels` on the screen (mode Pixels); never finer than the chart's texels.
struct GpuRefinement {
  enum class Mode { Level, Pixels } mode = Mode::Pixels;
  int halvings = 0;
  double pixels = 8;
};

struct DrawStyle {
  bool wireframe = false;
  bool colourByChart = false;
  Vec3 colour{0.93, 0.78, 0.62};
  Vec3 background{1, 1, 1};
};

struct FrameFigures {
  std::size_t patches = 0;
  std::uint64_t triangles = 0;
  double gpuMs = 0;  // the draw, to its finish (GPU timer, or the wall clock where that is longer)
};

// What both renderers share. drawMeasured: `draw` into `target` (bound, cleared to `background`,
// depth test on), with the triangles it made and its GPU time (to its finish). captureTriangles:
// the passes drawn with rasterisation off, once counting and once capturing the output
// `worldPosition` by transform feedback, each pass with its program in use (GL keeps one program
// through a capture); three corners a triangle, not welded, in pass order.
struct CapturePass {
  const gl::Program* program;
  std::function<void()> draw;  // must not change the program
};
FrameFigures drawMeasured(const gl::Framebuffer& target, const Vec3& background, const std::function<void()>& draw);
Mesh captureTriangles(const std::vector<CapturePass>& passes);

class AtlasRenderer {
public:
  AtlasRenderer();  // compiles its program in the current context (once per context)
  // Draws into `target` (bound here), cleared to the background first. `scene` bounds every item
  // (near and far planes).
  FrameFigures draw(const std::vector<DrawItem>& items, const Camera& camera, const Box& scene,
                    const GpuRefinement& gpu, const DrawStyle& style, const gl::Framebuffer& target) const;
  // The triangles the same draw makes, in world coordinates, three corners each (not welded).
  Mesh capture(const std::vector<DrawItem>& items, const Camera& camera, const Box& scene, const GpuRefinement& gpu) const;

private:
  // Uses and sets up the program: with the geometry stage for a wireframe or a capture.
  const gl::Program& prepare(const Camera& camera, const Box& scene, const GpuRefinement& gpu, const DrawStyle& style,
                             bool capturing) const;
  void drawItems(const gl::Program& program, const std::vector<DrawItem>& items) const;
  const gl::Program *program_, *direct_;
  std::size_t chunk_;  // patches a draw (0: all; on llvmpipe, softwareChunk)
  unsigned maxTessLevel_;
  gl::VertexArray vao_;  // none of its attributes are used: the patches come from a storage buffer
};

}  // namespace isoatlas::render
