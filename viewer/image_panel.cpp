#include "viewer/image_panel.h"

namespace isoatlas::viewer {

void ImagePanel::set(const Image& image) {
  if (!target_ || target_->width() != image.width || target_->height() != image.height)
    target_ = std::make_unique<gl::Framebuffer>(image.width, image.height);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(target_->colour().id(), 0, 0, 0, image.width, image.height, image.channels == 4 ? GL_RGBA : GL_RGB,
                      GL_UNSIGNED_BYTE, image.pixels.data());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
}

void ImagePanel::blit(int x, int top, int windowHeight) const {
  if (!target_) return;
  const int w = target_->width(), h = target_->height();
  glBlitNamedFramebuffer(target_->id(), 0, 0, 0, w, h, x, windowHeight - top, x + w, windowHeight - top - h, GL_COLOR_BUFFER_BIT,
                         GL_NEAREST);
}

}  // namespace isoatlas::viewer
