// A buffer through zlib's deflate (zlib format, as compress2 writes it) and back: the PNG writer's
// scanlines and the model file's chart codes.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace isoatlas {

// Inputs: `size` bytes at `data`; `level` 1 (fastest) to 9 (smallest). Output: the deflated bytes.
// Throws Error (a failure, naming `what`) when zlib cannot deflate them (out of memory).
std::vector<std::uint8_t> deflateBytes(const std::uint8_t* data, std::size_t size, int level, const std::string& what);

// Inputs: `size` deflated bytes at `data`. Output: exactly `outSize` bytes at `out`. False when the
// bytes are not a zlib stream, or it inflates to any other length (damaged input, never thrown).
bool inflateExactly(const std::uint8_t* data, std::size_t size, std::uint8_t* out, std::size_t outSize);

}  // namespace isoatlas
