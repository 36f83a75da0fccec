// Reading and writing volumes. The format follows the file name:
//   .nii .nii.gz .hdr (NIfTI-1 and NIfTI-2, nifticlib)   .nrrd .nhdr (NRRD, teem)   .inr .inr.gz (INRIMAGE-4)
//   a folder, or a .dcm file of one (a DICOM series, GDCM; read only)
// Readers check every size before allocating (the memory budget, core/memory_budget.h) and read NaN and infinite voxels as the
// background (backgroundNonFiniteVoxels, with one line saying how many);
// all failures throw isoatlas::Error naming the file and what was wrong.
#pragma once
#include <string>

#include "core/volume.h"

namespace isoatlas {

enum class VolumeFormat { Nifti, Nrrd, Inr, Dicom };

bool isVolumePath(const std::string& path);
bool isVolumeWritePath(const std::string& path);  // isVolumePath, less what isoatlas only reads (DICOM)
VolumeFormat volumeFormatOf(const std::string& path);  // throws Error for an unknown extension
// volumeFormatOf for a file to write: throws Error for a format isoatlas only reads (DICOM).
VolumeFormat volumeWriteFormatOf(const std::string& path);

// Which volume of a 4D file to read (NIfTI's dimension 4, or a NRRD's one non-spatial axis, as fMRI,
// diffusion and 3D Slicer's sequences hold them, counted from 0). Unset, a file of more than one is
// refused with a line giving the count; a 3D file is volume 0.
// Which series of a DICOM folder to read (its SeriesInstanceUID): unset, a folder of more than one
// is refused with a line listing them; a .dcm file is read as its own series.
struct VolumeReadOptions {
  std::int64_t volume = -1;
  std::string series;
};
Volume readVolume(const std::string& path, const VolumeReadOptions& options = {});
void writeVolume(const std::string& path, const Volume& volume);

// One reader and writer per format (core/volume_nifti.cpp, volume_nrrd.cpp, volume_inr.cpp).
Volume readNifti(const std::string& path, std::int64_t volume = -1);
void writeNifti(const std::string& path, const Volume& volume);
Volume readNrrd(const std::string& path, std::int64_t volume = -1);
void writeNrrd(const std::string& path, const Volume& volume);
Volume readInr(const std::string& path);
void writeInr(const std::string& path, const Volume& volume);
// core/volume_dicom.cpp: a folder (or a .dcm file of it) as one DICOM series of one slice a file,
// sorted along the slices' normal, in RAS with the rescale applied. Refuses gantry tilt, uneven
// slice spacing, multi-frame and colour files with one line each.
bool isDicomPath(const std::string& path);
Volume readDicom(const std::string& path, const std::string& series = {});

// For the readers of 4D files: throws Error unless `volume` (-1: unset) picks one of `volumes`,
// with the count and the option to give.
void requireVolumeIndex(const std::string& path, std::int64_t volumes, std::int64_t volume);

// validateVolumeHeader less the memory budget, for a source read in place (core/mapped_nifti.h), not
// into memory: dims (each >= 1, no overflow), spacing (finite, > 0) and direction (finite).
void validateVolumeGeometry(const Volume& v, const std::string& where);

// Splits an affine's 3x3 part (voxel index -> world) into spacing (column lengths) and direction
// (unit columns). Throws Error naming `where` if a column is zero or not finite.
void setGeometryFromAffine(Volume& v, const Mat3& linear, const Vec3& origin, const std::string& where);

}  // namespace isoatlas
