#include "core/volume_io.h"

#include "core/atomic_file.h"

#include <cstdio>
#include <filesystem>

#include "core/error.h"
#include "core/gz_file.h"
#include "core/numbers.h"
#include "core/progress.h"

namespace isoatlas {

bool isVolumePath(const std::string& path) {
  if (isDicomPath(path)) return true;
  for (const char* ext : {".nii", ".nii.gz", ".hdr", ".nrrd", ".nhdr", ".inr", ".inr.gz"})
    if (endsWith(path, ext)) return true;
  return false;
}

bool isVolumeWritePath(const std::string& path) { return isVolumePath(path) && !isDicomPath(path); }

VolumeFormat volumeFormatOf(const std::string& path) {
  if (endsWith(path, ".nii") || endsWith(path, ".nii.gz") || endsWith(path, ".hdr")) return VolumeFormat::Nifti;
  if (endsWith(path, ".nrrd") || endsWith(path, ".nhdr")) return VolumeFormat::Nrrd;
  if (endsWith(path, ".inr") || endsWith(path, ".inr.gz")) return VolumeFormat::Inr;
  if (isDicomPath(path)) return VolumeFormat::Dicom;
  throw Error(path + ": unknown volume format (expected .nii, .nii.gz, .nrrd, .nhdr, .inr, .inr.gz, or a DICOM folder)");
}

VolumeFormat volumeWriteFormatOf(const std::string& path) {
  const VolumeFormat format = volumeFormatOf(path);
  if (format == VolumeFormat::Dicom) throw Error(path + ": isoatlas reads DICOM but does not write it; write .nii.gz, .nrrd or .inr");
  return format;
}

void requireVolumeIndex(const std::string& path, std::int64_t volumes, std::int64_t volume) {
  if (volume < 0 && volumes > 1)
    throw Error(path + ": holds " + std::to_string(volumes) + " volumes (a 4D series); pick one with --volume N (Python: volume=N), 0 to " +
                std::to_string(volumes - 1));
  if (volume >= volumes)
    throw Error(path + ": holds " + std::to_string(volumes) + (volumes == 1 ? " volume" : " volumes") + "; --volume " +
                std::to_string(volume) + " is past the last (" + std::to_string(volumes - 1) + ")");
}

Volume readVolume(const std::string& path, const VolumeReadOptions& options) {
  const VolumeFormat format = volumeFormatOf(path);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec) && !(format == VolumeFormat::Dicom && std::filesystem::is_directory(path, ec)))
    throw Error(path + ": no such file");
  if (!options.series.empty() && format != VolumeFormat::Dicom) throw Error(path + ": --series picks a series of a DICOM folder; this is no DICOM");
  // INR and DICOM are read as 3D: asked for a later volume, refuse before reading them.
  if (format != VolumeFormat::Nifti && format != VolumeFormat::Nrrd && options.volume > 0)
    throw Error(path + ": holds one volume; --volume " + std::to_string(options.volume) + " is past it (0 is the only one)");
  Volume v;
  switch (format) {
    case VolumeFormat::Nifti: v = readNifti(path, options.volume); break;
    case VolumeFormat::Nrrd: v = readNrrd(path, options.volume); break;
    case VolumeFormat::Inr: v = readInr(path); break;
    case VolumeFormat::Dicom: v = readDicom(path, options.series); break;
  }
  const NonFiniteVoxels nonFinite = backgroundNonFiniteVoxels(v, path);
  v.nonFiniteVoxels = nonFinite.count;
  if (nonFinite.count > 0)
    logInfo(path + ": " + std::to_string(nonFinite.count) + " NaN or infinite voxels read as the background (" +
            shortNumber(nonFinite.background) + ", the smallest finite value)");
  return v;
}

void writeVolume(const std::string& path, const Volume& volume) {
  require(volume.data.size() == volume.voxelCount() * bytesPerVoxel(volume.type),
          path + ": volume data size does not match its dimensions");
  const VolumeFormat format = volumeWriteFormatOf(path);
  auto write = [&](const std::string& to) {
    switch (format) {
      case VolumeFormat::Nifti: writeNifti(to, volume); break;
      case VolumeFormat::Nrrd: writeNrrd(to, volume); break;
      case VolumeFormat::Inr: writeInr(to, volume); break;
      case VolumeFormat::Dicom: break;  // refused by volumeWriteFormatOf
    }
  };
  // A detached header (NRRD's .nhdr, NIfTI's .hdr) names its data file after itself, so the pair is
  // written where it stays.
  if (endsWith(path, ".nhdr") || endsWith(path, ".hdr")) write(path);
  else writeAtomically(path, write);
}

void setGeometryFromAffine(Volume& v, const Mat3& linear, const Vec3& origin, const std::string& where) {
  for (int c = 0; c < 3; ++c) {
    const Vec3 col = linear.column(c);
    const double len = norm(col);
    if (!std::isfinite(len) || len <= 0)
      throw Error(where + ": voxel-to-world transform has a zero or non-finite axis " + std::to_string(c));
    v.spacing[c] = len;
    for (int r = 0; r < 3; ++r) v.direction.m[r][c] = col[r] / len;
  }
  v.origin = origin;
}

}  // namespace isoatlas
