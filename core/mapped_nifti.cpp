#include "core/mapped_nifti.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <vector>

#include "core/error.h"
#include "core/numbers.h"
#include "core/progress.h"
#include "core/gz_file.h"

namespace isoatlas {
namespace {

// n stored values of type T from `at` as floats: byte order undone, then slope * v + inter in double
// where scaled (readNifti's setValue of the scaled type rounds it to float once, as here).
template <class T>
void convertStored(const std::byte* at, std::int64_t n, bool swapped, bool scaled, double slope, double inter, float* out) {
  for (std::int64_t i = 0; i < n; ++i, at += sizeof(T)) {
    std::byte b[sizeof(T)];
    std::memcpy(b, at, sizeof(T));
    if (swapped) std::reverse(b, b + sizeof(T));
    T value;
    std::memcpy(&value, b, sizeof(T));
    out[i] = scaled ? float(slope * double(value) + inter) : float(value);
  }
}

}  // namespace

bool isMappableVolumePath(const std::string& path) { return endsWith(path, ".nii") || endsWith(path, ".hdr"); }

MappedNifti::MappedNifti(const std::string& path, std::int64_t volume) : MappedNifti(path, readNiftiLayout(path, volume, false)) {}

MappedNifti::MappedNifti(const std::string& path, const NiftiLayout& layout) : VolumeSource(layout.geometry), layout_(layout) {
  if (endsWith(layout.dataFile, ".gz")) throw Error(path + ": its voxels are compressed (" + layout.dataFile + "), so they cannot be read in place");
  const int fd = ::open(layout.dataFile.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw Error(layout.dataFile + ": cannot be opened (" + std::strerror(errno) + ")");
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw Error(layout.dataFile + ": not a regular file");
  }
  const std::uint64_t voxels = layout.geometry.voxelCount(), perVoxel = bytesPerVoxel(layout.geometry.type);
  const std::uint64_t fileBytes = std::uint64_t(st.st_size);
  // voxels * perVoxel cannot overflow (validateVolumeGeometry bounds the count by 2^62), but may
  // pass the file's size: compare by division.
  if (layout.offset > fileBytes || voxels > (fileBytes - layout.offset) / perVoxel) {
    ::close(fd);
    throw Error(path + ": the file holds " + std::to_string(fileBytes) + " bytes, short of the " + std::to_string(voxels) + " " +
                scalarTypeName(layout.geometry.type) + " voxels its header places from byte " + std::to_string(layout.offset));
  }
  mapBytes_ = std::size_t(fileBytes);
  void* map = ::mmap(nullptr, mapBytes_, PROT_READ, MAP_PRIVATE, fd, 0);
  ::close(fd);  // the mapping keeps the file
  if (map == MAP_FAILED) throw Error(layout.dataFile + ": cannot be mapped (" + std::strerror(errno) + ")", ErrorKind::Failure);
  map_ = static_cast<const std::byte*>(map);

  // readVolume reads NaN and infinite voxels as the background, the smallest finite value: find both,
  // a slab of rows at a time.
  if (!isFloating(layout_.valueType())) return;
  const std::int64_t nx = layout.geometry.dims[0];
  std::vector<float> row(std::size_t(nx), 0.0f);
  float lowest = std::numeric_limits<float>::infinity();
  for (std::uint64_t first = 0; first < voxels; first += std::uint64_t(nx)) {
    readStored(std::size_t(first), nx, row.data());
    for (const float v : row) {
      if (std::isfinite(v)) lowest = std::min(lowest, v);
      else ++nonFinite_;
    }
  }
  if (nonFinite_ == 0) return;
  if (nonFinite_ == voxels) {
    ::munmap(const_cast<std::byte*>(map_), mapBytes_);
    throw Error(path + ": every voxel is NaN or infinite");
  }
  background_ = lowest;
  logInfo(path + ": " + std::to_string(nonFinite_) + " NaN or infinite voxels read as the background (" + shortNumber(lowest) +
          ", the smallest finite value)");
}

MappedNifti::~MappedNifti() {
  if (map_) ::munmap(const_cast<std::byte*>(map_), mapBytes_);
}

void MappedNifti::readStored(std::size_t first, std::int64_t n, float* out) const {
  const std::byte* at = map_ + layout_.offset + first * bytesPerVoxel(layout_.geometry.type);
  const bool sw = layout_.swapped, sc = layout_.scaled;
  const double a = layout_.slope, b = layout_.inter;
  switch (layout_.geometry.type) {
    case ScalarType::UInt8: convertStored<std::uint8_t>(at, n, sw, sc, a, b, out); break;
    case ScalarType::Int8: convertStored<std::int8_t>(at, n, sw, sc, a, b, out); break;
    case ScalarType::UInt16: convertStored<std::uint16_t>(at, n, sw, sc, a, b, out); break;
    case ScalarType::Int16: convertStored<std::int16_t>(at, n, sw, sc, a, b, out); break;
    case ScalarType::UInt32: convertStored<std::uint32_t>(at, n, sw, sc, a, b, out); break;
    case ScalarType::Int32: convertStored<std::int32_t>(at, n, sw, sc, a, b, out); break;
    case ScalarType::Float32: convertStored<float>(at, n, sw, sc, a, b, out); break;
    case ScalarType::Float64: convertStored<double>(at, n, sw, sc, a, b, out); break;
  }
}

void MappedNifti::readRow(std::int64_t x0, std::int64_t y, std::int64_t z, std::int64_t n, float* out) const {
  const auto& d = geometry().dims;
  readStored(std::size_t((z * d[1] + y) * d[0] + x0), n, out);
  if (nonFinite_ == 0) return;
  for (std::int64_t i = 0; i < n; ++i)
    if (!std::isfinite(out[i])) out[i] = background_;
}

bool MappedNifti::wholeBytes() const { return layout_.geometry.type == ScalarType::UInt8 && !layout_.scaled; }

std::shared_ptr<const VolumeSource> openVolumeSource(const std::string& path, const VolumeReadOptions& options, bool* mapped) {
  if (mapped) *mapped = false;
  if (isMappableVolumePath(path) && options.series.empty()) {
    std::error_code ec;
    require(std::filesystem::is_regular_file(path, ec), path + ": no such file");
    const NiftiLayout layout = readNiftiLayout(path, options.volume, false);
    if (!endsWith(layout.dataFile, ".gz")) {
      if (mapped) *mapped = true;
      return std::make_shared<const MappedNifti>(path, layout);
    }
  }
  return VolumeInMemory::compact(readVolume(path, options));
}

}  // namespace isoatlas
