#include "levelset/paged_phi_gpu.h"

#include "kLevelsetShaders.h"
#include "levelset/level_set.h"

namespace isoatlas::levelset {

const gl::EmbeddedShader* levelsetShaderFiles() { return gl::kLevelsetShaders; }

PagedPhiGpu::PagedPhiGpu(const PageManager& pages, unsigned poolTexture)
    : pageTable_(gl::Buffer::of(pages.pageTable())), pool_(poolTexture), poolPagesX_(pages.poolPagesX()),
      pageSize_(pages.pageSize()), pages_(pages.pages()) {}

PagedPhiGpu::PagedPhiGpu(const LevelSet& levelSet) : PagedPhiGpu(levelSet.pages(), levelSet.phiPoolTexture()) {
  if (pool_) return;
  const PageManager& pm = levelSet.pages();
  const int width = pm.poolPagesX() * pm.pageSize(), height = pm.capacity() / pm.poolPagesX() * pm.pageSize();
  uploaded_ = gl::Texture::texture2D(GL_R32F, width, height);
  glTextureSubImage2D(uploaded_.id(), 0, 0, 0, width, height, GL_RED, GL_FLOAT, levelSet.phiPoolOnHost());
  pool_ = uploaded_.id();
}

void PagedPhiGpu::bindData(unsigned poolBinding, unsigned pageTableBinding) const {
  glBindImageTexture(poolBinding, pool_, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
  pageTable_.bindBase(GL_SHADER_STORAGE_BUFFER, pageTableBinding);
}

void PagedPhiGpu::setUniforms(const gl::Program& program) const {
  glUniform1i(program.uniform("poolPagesX"), poolPagesX_);
  glUniform2i(program.uniform("pagesXY"), int(pages_[0]), int(pages_[1]));
}

}  // namespace isoatlas::levelset
