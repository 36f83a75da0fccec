#include "core/mapped_nifti.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

#include "core/error.h"
#include "core/numbers.h"
#include "core/progress.h"
#include "core/gz_file.h"

namespace isoatlas {
namespace {

// n stored values of type T from `at`, each as readNifti's Volume holds it (Volume::value): byte order
// undone, slope * v + inter where scaled, rounded to float where that Volume holds floats.
template <class T>
void storedValues(const std::byte* at, std::int64_t n, bool swapped, bool scaled, double slope, double inter, bool asFloat,
                  double* out) {
  for (std::int64_t i = 0; i < n; ++i, at += sizeof(T)) {
    std::byte b[sizeof(T)];
    std::memcpy(b, at, sizeof(T));
    if (swapped) std::reverse(b, b + sizeof(T));
    T value;
    std::memcpy(&value, b, sizeof(T));
    const double x = scaled ? slope * double(value) + inter : double(value);
    out[i] = asFloat ? double(float(x)) : x;
  }
}

// A gzip stream (its magic), which nifticlib and readNifti read through zlib whatever its name.
bool gzipped(const std::byte* bytes, std::size_t size) {
  return size >= 2 && bytes[0] == std::byte{0x1f} && bytes[1] == std::byte{0x8b};
}
bool gzipped(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  char magic[2] = {};
  return in.read(magic, 2) && gzipped(reinterpret_cast<const std::byte*>(magic), 2);
}

}  // namespace

bool isMappableVolumePath(const std::string& path) { return endsWith(path, ".nii") || endsWith(path, ".hdr"); }

MappedNifti::MappedNifti(const std::string& path, std::int64_t volume) : MappedNifti(path, readNiftiLayout(path, volume, false)) {}

MappedNifti::MappedNifti(const std::string& path, const NiftiLayout& layout, std::uint64_t residentMost)
    : VolumeSource(layout.geometry), layout_(layout), residentMost_(residentMost) {
  if (endsWith(layout.dataFile, ".gz") || gzipped(layout.dataFile))
    throw Error(path + ": its voxels are compressed (" + layout.dataFile + "), so they cannot be read in place");
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
  // a row at a time.
  if (!isFloating(layout_.valueType())) return;
  const std::int64_t nx = layout.geometry.dims[0];
  std::vector<double> row(std::size_t(nx), 0.0);
  double lowest = std::numeric_limits<double>::infinity();
  for (std::uint64_t first = 0; first < voxels; first += std::uint64_t(nx)) {
    readValues(std::size_t(first), nx, row.data());
    for (const double v : row) {
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

void MappedNifti::readValues(std::size_t first, std::int64_t n, double* out) const {
  // What the read may bring into the mapping: its bytes and the system page they start in (a row of
  // a few voxels maps a whole 4 KiB page).
  const std::uint64_t bytes = std::uint64_t(n) * bytesPerVoxel(layout_.geometry.type) + 4096;
  if (readSinceDrop_.fetch_add(bytes) + bytes > residentMost_) {
    // Read-only and private: dropped pages are read again from the file cache when next touched, so
    // a reader on another thread meanwhile is unaffected.
    readSinceDrop_ = 0;
    ::madvise(const_cast<std::byte*>(map_), mapBytes_, MADV_DONTNEED);
    ++drops_;
  }
  const std::byte* at = map_ + layout_.offset + first * bytesPerVoxel(layout_.geometry.type);
  const bool sw = layout_.swapped, sc = layout_.scaled, f = layout_.valueType() == ScalarType::Float32;
  const double a = layout_.slope, b = layout_.inter;
  switch (layout_.geometry.type) {
    case ScalarType::UInt8: storedValues<std::uint8_t>(at, n, sw, sc, a, b, f, out); break;
    case ScalarType::Int8: storedValues<std::int8_t>(at, n, sw, sc, a, b, f, out); break;
    case ScalarType::UInt16: storedValues<std::uint16_t>(at, n, sw, sc, a, b, f, out); break;
    case ScalarType::Int16: storedValues<std::int16_t>(at, n, sw, sc, a, b, f, out); break;
    case ScalarType::UInt32: storedValues<std::uint32_t>(at, n, sw, sc, a, b, f, out); break;
    case ScalarType::Int32: storedValues<std::int32_t>(at, n, sw, sc, a, b, f, out); break;
    case ScalarType::Float32: storedValues<float>(at, n, sw, sc, a, b, f, out); break;
    case ScalarType::Float64: storedValues<double>(at, n, sw, sc, a, b, f, out); break;
  }
}

void MappedNifti::readRow(std::int64_t x0, std::int64_t y, std::int64_t z, std::int64_t n, float* out) const {
  const auto& d = geometry().dims;
  const std::size_t first = std::size_t((z * d[1] + y) * d[0] + x0);
  // Non-finite is judged on the value as readNifti's Volume holds it (a double of 1e300 is finite
  // there, and becomes infinity only as a float), so a chunk at a time passes through doubles.
  constexpr std::int64_t kChunk = 64;
  double values[kChunk];
  for (std::int64_t i = 0; i < n; i += kChunk) {
    const std::int64_t m = std::min(kChunk, n - i);
    readValues(first + std::size_t(i), m, values);
    for (std::int64_t k = 0; k < m; ++k) out[i + k] = float(nonFinite_ > 0 && !std::isfinite(values[k]) ? background_ : values[k]);
  }
}

bool MappedNifti::wholeBytes() const { return layout_.geometry.type == ScalarType::UInt8 && !layout_.scaled; }

std::shared_ptr<const VolumeSource> openVolumeSource(const std::string& path, const VolumeReadOptions& options, bool* mapped) {
  if (mapped) *mapped = false;
  if (isMappableVolumePath(path) && options.series.empty()) {
    std::error_code ec;
    require(std::filesystem::is_regular_file(path, ec), path + ": no such file");
    const NiftiLayout layout = readNiftiLayout(path, options.volume, false);
    if (!endsWith(layout.dataFile, ".gz") && !gzipped(layout.dataFile)) {
      if (mapped) *mapped = true;
      return std::make_shared<const MappedNifti>(path, layout);
    }
  }
  return VolumeInMemory::compact(readVolume(path, options));
}

}  // namespace isoatlas
