#include "core/volume.h"
#include "core/volume_io.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/error.h"
#include "core/memory_budget.h"

namespace isoatlas {

std::size_t bytesPerVoxel(ScalarType t) {
  switch (t) {
    case ScalarType::UInt8: case ScalarType::Int8: return 1;
    case ScalarType::UInt16: case ScalarType::Int16: return 2;
    case ScalarType::UInt32: case ScalarType::Int32: case ScalarType::Float32: return 4;
    case ScalarType::Float64: return 8;
  }
  return 1;
}

const char* scalarTypeName(ScalarType t) {
  switch (t) {
    case ScalarType::UInt8: return "uint8";
    case ScalarType::Int8: return "int8";
    case ScalarType::UInt16: return "uint16";
    case ScalarType::Int16: return "int16";
    case ScalarType::UInt32: return "uint32";
    case ScalarType::Int32: return "int32";
    case ScalarType::Float32: return "float32";
    case ScalarType::Float64: return "float64";
  }
  return "?";
}

bool isFloating(ScalarType t) { return t == ScalarType::Float32 || t == ScalarType::Float64; }

namespace {
template <class T>
T load(const std::byte* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}
template <class T>
void store(std::byte* p, double v) {
  T t;
  if constexpr (std::is_floating_point_v<T>) {
    t = T(v);
  } else {
    v = std::round(v);
    v = std::clamp(v, double(std::numeric_limits<T>::lowest()), double(std::numeric_limits<T>::max()));
    t = T(v);
  }
  std::memcpy(p, &t, sizeof(T));
}
}  // namespace

Volume Volume::zeros(std::array<std::int64_t, 3> dims, ScalarType type) {
  Volume v;
  v.dims = dims;
  v.type = type;
  validateVolumeHeader(v, "new volume");
  v.data.assign(v.voxelCount() * bytesPerVoxel(type), std::byte{0});
  return v;
}

double Volume::value(std::size_t n) const {
  const std::byte* p = data.data() + n * bytesPerVoxel(type);
  switch (type) {
    case ScalarType::UInt8: return load<std::uint8_t>(p);
    case ScalarType::Int8: return load<std::int8_t>(p);
    case ScalarType::UInt16: return load<std::uint16_t>(p);
    case ScalarType::Int16: return load<std::int16_t>(p);
    case ScalarType::UInt32: return load<std::uint32_t>(p);
    case ScalarType::Int32: return load<std::int32_t>(p);
    case ScalarType::Float32: return load<float>(p);
    case ScalarType::Float64: return load<double>(p);
  }
  return 0;
}

void Volume::setValue(std::size_t n, double v) {
  std::byte* p = data.data() + n * bytesPerVoxel(type);
  switch (type) {
    case ScalarType::UInt8: store<std::uint8_t>(p, v); break;
    case ScalarType::Int8: store<std::int8_t>(p, v); break;
    case ScalarType::UInt16: store<std::uint16_t>(p, v); break;
    case ScalarType::Int16: store<std::int16_t>(p, v); break;
    case ScalarType::UInt32: store<std::uint32_t>(p, v); break;
    case ScalarType::Int32: store<std::int32_t>(p, v); break;
    case ScalarType::Float32: store<float>(p, v); break;
    case ScalarType::Float64: store<double>(p, v); break;
  }
}

Vec3 Volume::indexToWorld(const Vec3& ijk) const {
  return origin + direction * Vec3{ijk.x * spacing.x, ijk.y * spacing.y, ijk.z * spacing.z};
}

Vec3 Volume::worldToIndex(const Vec3& world) const {
  // direction is orthonormal for every volume we read, so its inverse is its transpose.
  const Vec3 d = world - origin;
  return {dot(direction.column(0), d) / spacing.x, dot(direction.column(1), d) / spacing.y,
          dot(direction.column(2), d) / spacing.z};
}

Volume Volume::sameGeometry(ScalarType newType) const {
  Volume v = zeros(dims, newType);
  v.spacing = spacing;
  v.origin = origin;
  v.direction = direction;
  return v;
}

std::vector<float> Volume::toFloat() const {
  std::vector<float> out(voxelCount());
  for (std::size_t n = 0; n < out.size(); ++n) out[n] = float(value(n));
  return out;
}

void validateVolumeHeader(const Volume& v, const std::string& where) {
  validateVolumeGeometry(v, where);
  const std::uint64_t count = std::uint64_t(v.dims[0]) * std::uint64_t(v.dims[1]) * std::uint64_t(v.dims[2]);
  const std::uint64_t perVoxel = bytesPerVoxel(v.type);
  requireWithinMemoryBudget(count > ~std::uint64_t(0) / perVoxel ? ~std::uint64_t(0) : count * perVoxel,
                            where + ": " + std::to_string(v.dims[0]) + " x " + std::to_string(v.dims[1]) + " x " +
                                std::to_string(v.dims[2]) + " " + scalarTypeName(v.type) + " voxels");
}

void validateVolumeGeometry(const Volume& v, const std::string& where) {
  std::uint64_t count = 1;
  for (int a = 0; a < 3; ++a) {
    const std::int64_t d = v.dims[a];
    if (d < 1)
      throw Error(where + ": dimension " + std::to_string(a) + " is " + std::to_string(d) + " (must be >= 1)");
    constexpr std::uint64_t kCountLimit = std::uint64_t(1) << 62;  // the byte count below cannot overflow
    if (std::uint64_t(d) > kCountLimit || count > kCountLimit / std::uint64_t(d))
      throw Error(where + ": dimensions " + std::to_string(v.dims[0]) + " x " + std::to_string(v.dims[1]) + " x " +
                  std::to_string(v.dims[2]) + " are too large");
    count *= std::uint64_t(d);
  }
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(v.spacing[a]) || v.spacing[a] <= 0)
      throw Error(where + ": spacing along axis " + std::to_string(a) + " is " + std::to_string(v.spacing[a]) +
                  " (must be finite and > 0)");
    if (!std::isfinite(v.origin[a])) throw Error(where + ": origin is not finite");
    for (int b = 0; b < 3; ++b)
      if (!std::isfinite(v.direction.m[a][b])) throw Error(where + ": direction matrix is not finite");
  }
}

void requireFiniteVoxels(const Volume& v, const std::string& where) {
  if (!isFloating(v.type)) return;
  for (std::size_t n = 0, count = v.voxelCount(); n < count; ++n) {
    const double x = v.value(n);
    if (!std::isfinite(x)) {
      const std::size_t i = n % std::size_t(v.dims[0]);
      const std::size_t j = (n / std::size_t(v.dims[0])) % std::size_t(v.dims[1]);
      const std::size_t k = n / (std::size_t(v.dims[0]) * std::size_t(v.dims[1]));
      throw Error(where + ": voxel (" + std::to_string(i) + "," + std::to_string(j) + "," + std::to_string(k) +
                  ") is " + (std::isnan(x) ? "NaN" : "infinite") + "; isoatlas needs finite values");
    }
  }
}

NonFiniteVoxels backgroundNonFiniteVoxels(Volume& v, const std::string& where) {
  if (!isFloating(v.type)) return {};
  const std::size_t count = v.voxelCount();
  double background = std::numeric_limits<double>::infinity();
  std::uint64_t nonFinite = 0;
  for (std::size_t n = 0; n < count; ++n) {
    const double x = v.value(n);
    if (std::isfinite(x)) background = std::min(background, x);
    else ++nonFinite;
  }
  if (nonFinite == 0) return {};
  if (nonFinite == count) throw Error(where + ": every voxel is NaN or infinite");
  for (std::size_t n = 0; n < count; ++n)
    if (!std::isfinite(v.value(n))) v.setValue(n, background);
  return {nonFinite, background};
}

ValueRange valueRange(const Volume& v) {
  ValueRange r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (std::size_t n = 0, count = v.voxelCount(); n < count; ++n) {
    const double x = v.value(n);
    r.min = std::min(r.min, x);
    r.max = std::max(r.max, x);
  }
  if (v.voxelCount() == 0) r = {0, 0};
  return r;
}

}  // namespace isoatlas
