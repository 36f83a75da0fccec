#include "core/volume_source.h"

#include <cmath>
#include <cstring>
#include <string>

#include "core/error.h"

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

// Whether every voxel, as readRow gives it, is a whole number from 0 to 255.
bool wholeBytesIn(const Volume& volume) {
  if (volume.type == ScalarType::UInt8) return true;
  for (std::size_t n = 0; n < volume.voxelCount(); ++n) {
    const float v = float(volume.value(n));
    if (!(v >= 0 && v <= 255 && v == std::floor(v))) return false;
  }
  return true;
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
  require(volume_.data.size() == volume_.voxelCount() * bytesPerVoxel(volume_.type),
          "a volume's voxels do not fill its dimensions (" + std::to_string(volume_.data.size()) + " bytes)");
  wholeBytes_ = wholeBytesIn(volume_);
}

std::shared_ptr<const VolumeInMemory> VolumeInMemory::compact(const Volume& volume) {
  const bool bytes = wholeBytesIn(volume);
  const ScalarType type = bytes ? ScalarType::UInt8 : ScalarType::Float32;
  if (volume.type == type) return std::make_shared<const VolumeInMemory>(volume);
  Volume converted = volume.sameGeometry(type);
  for (std::size_t n = 0; n < volume.voxelCount(); ++n) {
    const float v = float(volume.value(n));  // as readRow gives it
    if (bytes) converted.data[n] = std::byte(std::uint8_t(v));
    else std::memcpy(converted.data.data() + n * sizeof(float), &v, sizeof v);
  }
  return std::make_shared<const VolumeInMemory>(std::move(converted));
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
