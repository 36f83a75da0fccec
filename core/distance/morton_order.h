// mortonOrder: points along the Morton (Z-order) curve, 10 bits a coordinate within their bounding
// box, so that neighbours in the order are mostly neighbours in space: TriangleTree splits its
// triangles along it, and mesh_distance queries its samples in it (each query hinted by the last).
//   count  how many points (below 2^32)
//   at     the i-th point, for i in [0, count)
// Returns a key per point, its code in the high 32 bits and i in the low ones, sorted: by code, then by
// index (one order whatever the threads did).
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/vec.h"

namespace isoatlas {

std::vector<std::uint64_t> mortonOrder(std::size_t count, const std::function<Vec3(std::size_t)>& at);

inline std::uint32_t mortonCode(std::uint64_t key) { return std::uint32_t(key >> 32); }
inline std::uint32_t mortonIndex(std::uint64_t key) { return std::uint32_t(key); }

}  // namespace isoatlas
