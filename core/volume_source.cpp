#include "core/volume_source.h"

#include <cmath>
#include <cstring>

namespace isoatlas {
namespace {

// As Volume::toFloat converts (each voxel's value, rounded to float once).
template <class T>
void convertRow(const std::byte* data, std::size_t from, std::int64_t n, float* out) {
  const std::byte* at = data + from * sizeof(T);
  for (std::int64_t i = 0; i < n; ++i, at += sizeof(T)) {
    T value;
    std::memcpy(&value, at, sizeof(T));
    out[i] = float(value);
  }
}

}  // namespace

VolumeSource::VolumeSource(const Volume& v) {
  geometry_.dims = v.dims;
  geometry_.spacing = v.spacing;
  geometry_.origin = v.origin;
  geometry_.direction = v.direction;
  geometry_.type = v.type;
}

VolumeInMemory::VolumeInMemory(Volume volume) : VolumeSource(volume), volume_(std::move(volume)) {
  wholeBytes_ = true;
  if (volume_.type == ScalarType::UInt8) return;
  for (std::size_t n = 0; n < volume_.voxelCount() && wholeBytes_; ++n) {
    const float v = float(volume_.value(n));  // as readRow gives it
    wholeBytes_ = v >= 0 && v <= 255 && v == std::floor(v);
  }
}

void VolumeInMemory::readRow(std::int64_t x0, std::int64_t y, std::int64_t z, std::int64_t n, float* out) const {
  const std::size_t from = volume_.index(x0, y, z);
  const std::byte* d = volume_.data.data();
  switch (volume_.type) {
    case ScalarType::UInt8: return convertRow<std::uint8_t>(d, from, n, out);
    case ScalarType::Int8: return convertRow<std::int8_t>(d, from, n, out);
    case ScalarType::UInt16: return convertRow<std::uint16_t>(d, from, n, out);
    case ScalarType::Int16: return convertRow<std::int16_t>(d, from, n, out);
    case ScalarType::UInt32: return convertRow<std::uint32_t>(d, from, n, out);
    case ScalarType::Int32: return convertRow<std::int32_t>(d, from, n, out);
    case ScalarType::Float32: return convertRow<float>(d, from, n, out);
    case ScalarType::Float64: return convertRow<double>(d, from, n, out);
  }
}

}  // namespace isoatlas
