#include "core/image.h"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include "core/atomic_file.h"
#include "core/error.h"

namespace isoatlas {

void writePng(const std::string& path, const Image& image) {
  require(image.width > 0 && image.height > 0 && image.pixels.size() == std::size_t(image.width) * image.height * image.channels,
          path + ": image has no pixels or inconsistent size");
  writeAtomically(path, [&](const std::string& to) {
    if (!stbi_write_png(to.c_str(), image.width, image.height, image.channels, image.pixels.data(), image.width * image.channels))
      throw Error(path + ": could not write PNG", ErrorKind::Failure);
  });
}

Image readPng(const std::string& path) {
  int w = 0, h = 0, c = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &c, 0);
  if (!data) throw Error(path + ": not a readable PNG: " + stbi_failure_reason());
  Image img(w, h, c);
  std::copy(data, data + img.pixels.size(), img.pixels.begin());
  stbi_image_free(data);
  return img;
}

}  // namespace isoatlas
