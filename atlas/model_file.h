// The .isoatlas model file: what `isoatlas build` makes and the later stages read. A little-endian
// binary file: the magic "ISOATLAS", a format version, then tagged sections, each a 4-byte tag, a
// 64-bit byte length and its payload, so readers can skip what they do not know:
//   HEAD  chart size (u32)
//   DENS  the dense mesh: vertex count (u64), positions (f64 x 3), triangle count (u64), corners (u32 x 3)
//   BASE  the base mesh: vertex count, positions, dense vertex (i64, -1 for split vertices), triangle
//         count, corners, tile count, tiles (u32 x 2), then per dense vertex its base triangle (u32)
//         and barycentric coordinates (f64 x 3)
// Version 1 holds no charts yet: the atlas issue adds them as a section of their own.
#pragma once
#include <string>

#include "core/mesh.h"
#include "multires/base_mesh.h"

namespace isoatlas::atlas {

struct Model {
  std::uint32_t chartSize = 33;
  Mesh dense;
  multires::BaseMesh base;
};

void writeModel(const std::string& path, const Model& model);

// Checks every count against the bytes the file holds, every index against its range, and that
// the coordinates are finite; throws Error(BadInput) naming the file and the byte offset.
Model readModel(const std::string& path);

}  // namespace isoatlas::atlas
