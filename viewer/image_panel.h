// ImagePanel: a picture made on the CPU (slices, a rendered surface, the atlas preview) shown in the
// window: uploaded to a texture when it changes, copied into the window by a blit (no shader), or
// drawn inside a Dear ImGui panel. Needs the window's GL context current.
#pragma once
#include <memory>

#include "core/gl/resources.h"
#include "core/image.h"

namespace isoatlas::viewer {

class ImagePanel {
public:
  void set(const Image& image);  // RGB or RGBA, rows top to bottom
  bool empty() const { return !target_; }
  int width() const { return target_ ? target_->width() : 0; }
  int height() const { return target_ ? target_->height() : 0; }
  // Its top-left corner at window pixel (x, top), the window `windowHeight` pixels high (GL's rows
  // run bottom to top, the image's top to bottom: the blit flips).
  void blit(int x, int top, int windowHeight) const;
  unsigned texture() const { return target_ ? target_->colour().id() : 0; }  // for ImGui::Image

private:
  std::unique_ptr<gl::Framebuffer> target_;  // its colour texture holds the picture
};

}  // namespace isoatlas::viewer
