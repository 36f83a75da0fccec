// PagedPhiGpu: a level set's phi for shaders outside the solver, read straight from its pages
// (levelset/shaders/paged_phi.glsl; Lefohn's thesis, sec. 3.4: no dense copy). It holds the page
// table on the GPU and the pool texture: the GPU solver's own, or the CPU solver's pool uploaded (its
// contiguous slots laid out as the texture's). Made again after the level set changes. Needs the GL
// context the texture lives in current.
#pragma once
#include "core/gl/program.h"
#include "core/gl/resources.h"
#include "core/gl/shader_library.h"
#include "levelset/page_manager.h"

namespace isoatlas::levelset {

class LevelSet;

// The levelset library's shader table (paged_phi.glsl among them), to join with a reader's own.
const gl::EmbeddedShader* levelsetShaderFiles();

class PagedPhiGpu {
public:
  // From the pages and a pool texture (r32f) the caller keeps alive.
  PagedPhiGpu(const PageManager& pages, unsigned poolTexture);
  // From a level set on either backend (the CPU's pool uploaded into a texture of this object's).
  explicit PagedPhiGpu(const LevelSet& levelSet);
  // The pool at an image unit and the page table at a storage-buffer binding (POOL_BINDING and
  // PAGE_TABLE_BINDING in the shader).
  void bindData(unsigned poolBinding = 0, unsigned pageTableBinding = 0) const;
  // poolPagesX and pagesXY of the program in use.
  void setUniforms(const gl::Program& program) const;
  int pageSize() const { return pageSize_; }

private:
  gl::Buffer pageTable_;
  gl::Texture uploaded_;  // the CPU's pool, when it came from there
  unsigned pool_ = 0;
  int poolPagesX_ = 0, pageSize_ = 0;
  std::array<std::int64_t, 3> pages_{};
};

}  // namespace isoatlas::levelset
