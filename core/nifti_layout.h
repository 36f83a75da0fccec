// Where a NIfTI-1 or NIfTI-2 file keeps one volume's voxels, and what they mean, from its header
// alone (nifticlib parses it): the reader into memory (readNifti) and the one in place (MappedNifti,
// core/mapped_nifti.h) share it, so that the two cannot read a header differently.
#pragma once
#include <cstdint>
#include <string>

#include "core/volume.h"

namespace isoatlas {

struct NiftiLayout {
  Volume geometry;       // dims, spacing, origin, direction and the stored scalar type; no voxels
  std::string dataFile;  // the file holding the voxels: the .nii itself, or a .hdr's .img (maybe .gz)
  std::uint64_t offset = 0;  // the chosen volume's first byte in dataFile (uncompressed)
  bool swapped = false;      // stored in the other byte order
  // scl_slope and scl_inter, applied when `scaled`: the voxels are then slope * stored + inter, of
  // type scaledType (Float64 for a Float64 file, else Float32), as nibabel's get_fdata reads them.
  double slope = 1, inter = 0;
  bool scaled = false;
  ScalarType scaledType = ScalarType::Float32;
  ScalarType valueType() const { return scaled ? scaledType : geometry.type; }
};

// Throws Error naming `path` for a header isoatlas refuses (not NIfTI, more than 4 dimensions, an
// unknown datatype, a bad affine or size, `volume` outside a 4D file's). withinBudget: the voxels,
// as valueType, must also fit the memory budget (a reader into memory asks it; one in place need not).
NiftiLayout readNiftiLayout(const std::string& path, std::int64_t volume, bool withinBudget);

}  // namespace isoatlas
