// SmoothSurface: the smooth mode. The model's tiles as a Catmull-Clark cage (face i = tile i, its
// corners p, s, q, r, so a face's (u, v) is its chart's), whose limit surface OpenSubdiv evaluates
// (Far: adaptive refinement and patch table, Gregory-basis end caps; Osd: its GLSL patch shaders in
// our tessellation pipeline), optionally with the atlas's detail added as a displacement along the
// limit normal. Without displacement it is OpenSubdiv's own adaptive tessellation of the base mesh,
// the benchmark's peer. Drawn into the current GL context like AtlasRenderer, to the same fragment
// shader (wireframe: base faces' borders brown).
//   tessLevel: OpenSubdiv's uniform level T; a base face gets 2T segments a side, 8 T^2 triangles
//   when T is a multiple of 2^(isolation - 1) and 2T <= 64.
#pragma once
#include <memory>
#include <vector>

#include "atlas/model_file.h"
#include "render/atlas_render.h"

namespace isoatlas::render {

class SmoothSurface {
public:
  // `textures`: the model's atlas on the GPU (the displacement), kept by reference. Throws
  // Error(BadInput) for an isolation level outside 1..6.
  SmoothSurface(const atlas::Model& model, const AtlasTextures& textures, int isolation = 2);
  ~SmoothSurface();
  std::size_t baseFaces() const { return faces_; }
  std::size_t patches() const { return patches_; }

  FrameFigures draw(const std::vector<Vec3>& offsets, const Camera& camera, const Box& scene, int tessLevel, bool displaced,
                    const DrawStyle& style, const gl::Framebuffer& target) const;
  // The triangles the same draw makes, in world coordinates, three corners each (not welded).
  Mesh capture(const std::vector<Vec3>& offsets, const Camera& camera, const Box& scene, int tessLevel, bool displaced) const;

private:
  struct PatchArray {
    int type, controlVertices, patches, indexBase, primitiveIdBase;
  };
  void setUniforms(const Camera& camera, const Box& scene, int tessLevel, bool displaced, const DrawStyle& style) const;
  // Draws the patch arrays of one type (-1: all) for each offset, using their programs (`direct`:
  // those without the geometry stage).
  void drawArrays(const std::vector<Vec3>& offsets, int type, bool direct) const;
  const AtlasTextures* textures_;
  std::size_t faces_ = 0, patches_ = 0;
  gl::Buffer controlVertices_, indices_, patchParams_;
  gl::Texture patchParamTexture_;
  gl::VertexArray vao_;
  std::vector<PatchArray> arrays_;
  bool chunked_ = false;  // llvmpipe restarts gl_PrimitiveID every 1024 indices: draw in chunks there
};

}  // namespace isoatlas::render
