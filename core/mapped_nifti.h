// MappedNifti: a VolumeSource that reads an uncompressed NIfTI-1 or NIfTI-2 file (.nii, or a .hdr
// with its .img) in place, through a read-only memory map, so that a volume larger than memory is
// read only where the level set's band reaches (issue 67). Each row is converted as readNifti reads
// the file (byte order, scl_slope and scl_inter, NaN and infinite voxels as the background: the
// smallest finite value), so the two give the same floats voxel for voxel.
//   - The header is nifticlib's, parsed as readNifti parses it (core/nifti_layout.h). The memory
//     budget does not apply: the voxels are not read into memory.
//   - The file must hold every voxel its header promises (checked when opened). It must not shrink
//     while mapped: the system would then stop the program at the first read past its end.
//   - heldBytes is 0: the pages read stay in the system's file cache, which it reclaims as it needs.
//     The process's own mapping of them is dropped (madvise) each time reads since the last drop
//     may have mapped residentMost bytes (each read counted with the 4 KiB page it starts in), so
//     its resident memory does not grow with the volume (a page read again comes back from the cache).
//   - A floating-point file is scanned once when opened, for its non-finite voxels and background.
// openVolumeSource picks the source for a path: mapped where the file can be, else read into memory.
#pragma once
#include <atomic>
#include <memory>
#include <string>

#include "core/nifti_layout.h"
#include "core/volume_io.h"
#include "core/volume_source.h"

namespace isoatlas {

class MappedNifti final : public VolumeSource {
public:
  // Throws Error naming `path` for a header readNifti would refuse, compressed voxels, or a file
  // shorter than its header says.
  static constexpr std::uint64_t kResidentMost = std::uint64_t(256) << 20;
  explicit MappedNifti(const std::string& path, std::int64_t volume = -1);
  MappedNifti(const std::string& path, const NiftiLayout& layout, std::uint64_t residentMost = kResidentMost);
  ~MappedNifti() override;
  MappedNifti(const MappedNifti&) = delete;
  MappedNifti& operator=(const MappedNifti&) = delete;

  void readRow(std::int64_t x0, std::int64_t y, std::int64_t z, std::int64_t n, float* out) const override;
  bool wholeBytes() const override;
  std::uint64_t heldBytes() const override { return 0; }
  std::uint64_t nonFiniteVoxels() const { return nonFinite_; }
  std::uint64_t mappingDrops() const { return drops_.load(); }  // times the mapping's pages were dropped

private:
  // n voxels from voxel `first` (counted over the volume), each as readNifti's Volume holds it (non-finite kept).
  void readValues(std::size_t first, std::int64_t n, double* out) const;

  NiftiLayout layout_;
  const std::byte* map_ = nullptr;
  std::size_t mapBytes_ = 0;
  std::uint64_t nonFinite_ = 0;
  double background_ = 0;
  std::uint64_t residentMost_;
  mutable std::atomic<std::uint64_t> readSinceDrop_{0}, drops_{0};
};

// Whether `path` names an uncompressed NIfTI file whose voxels could be mapped (its extension: .nii
// or .hdr); MappedNifti still refuses a .hdr whose .img is compressed.
bool isMappableVolumePath(const std::string& path);

// The volume at `path` as a source: mapped where isMappableVolumePath (and the voxels are not
// compressed: a .nii that is gzip inside is read whole), else read whole (readVolume, with its checks and its memory budget) and held
// compactly (VolumeInMemory::compact). `mapped`, when given, says which.
std::shared_ptr<const VolumeSource> openVolumeSource(const std::string& path, const VolumeReadOptions& options = {},
                                                     bool* mapped = nullptr);

}  // namespace isoatlas
