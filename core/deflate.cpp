#include "core/deflate.h"

#include <zlib.h>

#include "core/error.h"

namespace isoatlas {

std::vector<std::uint8_t> deflateBytes(const std::uint8_t* data, std::size_t size, int level, const std::string& what) {
  uLongf packedSize = compressBound(uLong(size));
  std::vector<std::uint8_t> packed(packedSize);
  if (compress2(packed.data(), &packedSize, data, uLong(size), level) != Z_OK)
    throw Error(what + ": zlib could not deflate the bytes", ErrorKind::Failure);
  packed.resize(packedSize);
  return packed;
}

bool inflateExactly(const std::uint8_t* data, std::size_t size, std::uint8_t* out, std::size_t outSize) {
  uLongf inflated = uLongf(outSize);
  return uncompress(out, &inflated, data, uLong(size)) == Z_OK && inflated == outSize;
}

}  // namespace isoatlas
