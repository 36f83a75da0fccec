// Volume: a 3D scalar image with its place in the world, as read from NIfTI, NRRD or INR.
// Voxel (i,j,k) is stored at data offset ((k*ny + j)*nx + i) * bytesPerVoxel, x fastest.
// World (mm, RAS like nibabel and 3D Slicer) = origin + direction * (spacing .* (i,j,k)).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec.h"

namespace isoatlas {

enum class ScalarType { UInt8, Int8, UInt16, Int16, UInt32, Int32, Float32, Float64 };

std::size_t bytesPerVoxel(ScalarType t);
const char* scalarTypeName(ScalarType t);  // "uint8", "float32", ...
bool isFloating(ScalarType t);

struct Volume {
  std::array<std::int64_t, 3> dims{0, 0, 0};
  Vec3 spacing{1, 1, 1};  // mm between voxel centres along i, j, k
  Vec3 origin{0, 0, 0};   // world position of voxel (0,0,0)
  Mat3 direction;         // columns: unit world directions of the i, j, k axes
  ScalarType type = ScalarType::Float32;
  std::vector<std::byte> data;
  // NaN or infinite voxels the file held, read as the background (backgroundNonFiniteVoxels).
  std::uint64_t nonFiniteVoxels = 0;

  // A zero-filled volume of the given size and type; throws Error on sizes past volumeByteLimit().
  static Volume zeros(std::array<std::int64_t, 3> dims, ScalarType type);

  std::size_t voxelCount() const { return std::size_t(dims[0]) * std::size_t(dims[1]) * std::size_t(dims[2]); }
  std::size_t index(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return std::size_t((k * dims[1] + j) * dims[0] + i);
  }
  // Value of voxel n converted to double, whatever the scalar type.
  double value(std::size_t n) const;
  void setValue(std::size_t n, double v);  // rounds and clamps for integer types
  double at(std::int64_t i, std::int64_t j, std::int64_t k) const { return value(index(i, j, k)); }

  Vec3 indexToWorld(const Vec3& ijk) const;
  Vec3 worldToIndex(const Vec3& world) const;
  // Copies this volume's geometry (dims, spacing, origin, direction) onto a new one of another type.
  Volume sameGeometry(ScalarType newType) const;
  std::vector<float> toFloat() const;
};

// Checks dims (each >= 1, product and bytes within the memory budget (core/memory_budget.h), no overflow), spacing (finite,
// > 0) and direction (finite); throws Error naming `where` otherwise.
void validateVolumeHeader(const Volume& v, const std::string& where);
// Throws Error naming the first NaN or infinite voxel (i,j,k) of a floating-point volume.
void requireFiniteVoxels(const Volume& v, const std::string& where);
// Sets every NaN or infinite voxel of a floating-point volume to the background, its smallest finite
// value (outside every threshold and isovalue above it: resampled SPM and FSL outputs hold NaN
// outside the field of view), and returns how many there were and that value. Throws Error naming
// `where` when no voxel is finite.
struct NonFiniteVoxels {
  std::uint64_t count = 0;
  double background = 0;  // meaningful when count > 0
};
NonFiniteVoxels backgroundNonFiniteVoxels(Volume& v, const std::string& where);

struct ValueRange {
  double min = 0, max = 0;
};
ValueRange valueRange(const Volume& v);

}  // namespace isoatlas
