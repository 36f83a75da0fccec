// mortonOrder: points along the Morton (Z-order) curve, 21 bits a coordinate within their bounding
// box, so that neighbours in the order are mostly neighbours in space: TriangleTree splits its
// triangles along it, and mesh_distance queries its samples in it (each query hinted by the last).
//   count  how many points
//   at     the i-th point, for i in [0, count)
// Returns a key per point, sorted by code and then by index: one order whatever the threads did.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/vec.h"

namespace isoatlas {

struct MortonKey {
  std::uint64_t code;
  std::uint32_t index;
};
std::vector<MortonKey> mortonOrder(std::size_t count, const std::function<Vec3(std::size_t)>& at);

}  // namespace isoatlas
