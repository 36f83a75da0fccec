#include "levelset/paged_phi_gpu.h"

#include <algorithm>
#include <vector>

#include "kLevelsetShaders.h"
#include "levelset/level_set.h"

namespace isoatlas::levelset {

const gl::EmbeddedShader* levelsetShaderFiles() { return gl::kLevelsetShaders; }

PagedPhiGpu::PagedPhiGpu(const PageManager& pages, unsigned poolTexture)
    : pageTable_(gl::Buffer::of(pages.pageTable())), pool_(poolTexture), poolPagesX_(pages.poolPagesX()),
      pageSize_(pages.pageSize()), pages_(pages.pages()) {}

namespace {

// The host pool's slots laid out as in the GPU's pool texture (PoolLayout::Texture): a contiguous
// pool of thousands of slots is far taller than a texture may be.
std::vector<float> textureLayout(const PageManager& pm, const float* pool) {
  const std::size_t P = std::size_t(pm.pageSize()), perRow = std::size_t(textureSlotsPerRow(pm.pageSize()));
  const std::size_t slots = std::size_t(pm.capacity()), rows = (slots + perRow - 1) / perRow, width = perRow * P;
  std::vector<float> out(rows * P * width, 0.0f);
  for (std::size_t s = 0; s < slots; ++s)
    for (std::size_t y = 0; y < P; ++y)
      std::copy_n(pool + pm.slotTexel(std::int32_t(s), 0, std::int64_t(y)), P, out.data() + ((s / perRow) * P + y) * width + (s % perRow) * P);
  return out;
}

}  // namespace

PagedPhiGpu::PagedPhiGpu(const LevelSet& levelSet) : PagedPhiGpu(levelSet.pages(), levelSet.phiPoolTexture()) {
  if (pool_) return;
  const PageManager& pm = levelSet.pages();
  poolPagesX_ = textureSlotsPerRow(pm.pageSize());
  const int width = poolPagesX_ * pm.pageSize(), height = (pm.capacity() + poolPagesX_ - 1) / poolPagesX_ * pm.pageSize();
  uploaded_ = gl::Texture::texture2D(GL_R32F, width, height);
  const std::vector<float> texels = textureLayout(pm, levelSet.phiPoolOnHost());
  glTextureSubImage2D(uploaded_.id(), 0, 0, 0, width, height, GL_RED, GL_FLOAT, texels.data());
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
