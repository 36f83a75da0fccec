// NIfTI-1 and NIfTI-2 through nifticlib 3 (libnifti2). nifticlib parses the header (readNiftiLayout,
// core/nifti_layout.h); the voxel data is read here in bounded chunks so a lying header cannot make us
// allocate what the file does not hold.
#include <nifti2_io.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

#include "core/error.h"
#include "core/gz_file.h"
#include "core/nifti_layout.h"
#include "core/volume_io.h"

namespace isoatlas {
namespace {

struct NiftiDeleter {
  void operator()(nifti_image* nim) const {
    if (nim) nifti_image_free(nim);
  }
};
using NiftiPtr = std::unique_ptr<nifti_image, NiftiDeleter>;

bool scalarTypeFromNifti(int datatype, ScalarType& out) {
  switch (datatype) {
    case DT_UINT8: out = ScalarType::UInt8; return true;
    case DT_INT8: out = ScalarType::Int8; return true;
    case DT_UINT16: out = ScalarType::UInt16; return true;
    case DT_INT16: out = ScalarType::Int16; return true;
    case DT_UINT32: out = ScalarType::UInt32; return true;
    case DT_INT32: out = ScalarType::Int32; return true;
    case DT_FLOAT32: out = ScalarType::Float32; return true;
    case DT_FLOAT64: out = ScalarType::Float64; return true;
    default: return false;
  }
}

int niftiDatatype(ScalarType t) {
  switch (t) {
    case ScalarType::UInt8: return DT_UINT8;
    case ScalarType::Int8: return DT_INT8;
    case ScalarType::UInt16: return DT_UINT16;
    case ScalarType::Int16: return DT_INT16;
    case ScalarType::UInt32: return DT_UINT32;
    case ScalarType::Int32: return DT_INT32;
    case ScalarType::Float32: return DT_FLOAT32;
    case ScalarType::Float64: return DT_FLOAT64;
  }
  return DT_FLOAT32;
}

Mat3 linearPart(const nifti_dmat44& a) {
  Mat3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m.m[r][c] = a.m[r][c];
  return m;
}

}  // namespace

NiftiLayout readNiftiLayout(const std::string& path, std::int64_t volume, bool withinBudget) {
  nifti_set_debug_level(0);  // nifticlib's own chatter would break the one-line error contract
  NiftiPtr nim(nifti_image_read(path.c_str(), 0));
  if (!nim) throw Error(path + ": not a readable NIfTI-1/NIfTI-2 file (bad or truncated header)");

  if (nim->ndim < 1 || nim->ndim > 7) throw Error(path + ": NIfTI dim[0] is " + std::to_string(nim->ndim));
  for (int d = 5; d <= nim->ndim; ++d)
    if (nim->dim[d] > 1)
      throw Error(path + ": has " + std::to_string(nim->dim[d]) + " values along dimension " + std::to_string(d) +
                  "; isoatlas reads 3D scalar volumes, or one volume of a 4D series");
  const std::int64_t volumes = nim->ndim >= 4 ? std::max<std::int64_t>(nim->dim[4], 1) : 1;
  requireVolumeIndex(path, volumes, volume);
  NiftiLayout layout;
  Volume& v = layout.geometry;
  if (!scalarTypeFromNifti(nim->datatype, v.type))
    throw Error(path + ": unsupported NIfTI datatype " + std::to_string(nim->datatype) + " (" +
                nifti_datatype_string(nim->datatype) + ")");
  for (int a = 0; a < 3; ++a) v.dims[a] = a < nim->ndim ? nim->dim[a + 1] : 1;
  // sform first, then qform, as nibabel and 3D Slicer do; nifticlib fills qto_xyz from pixdim
  // when neither code is set, as ITK does.
  const nifti_dmat44& affine = nim->sform_code > 0 ? nim->sto_xyz : nim->qto_xyz;
  setGeometryFromAffine(v, linearPart(affine), {affine.m[0][3], affine.m[1][3], affine.m[2][3]}, path);
  if (withinBudget) validateVolumeHeader(v, path);
  else validateVolumeGeometry(v, path);
  // scl_slope and scl_inter make the voxels real numbers: the limit holds for those too, checked
  // before anything is read.
  layout.slope = nim->scl_slope, layout.inter = nim->scl_inter;
  layout.scaled = std::isfinite(layout.slope) && std::isfinite(layout.inter) && layout.slope != 0 &&
                  (layout.slope != 1 || layout.inter != 0);
  layout.scaledType = v.type == ScalarType::Float64 ? ScalarType::Float64 : ScalarType::Float32;
  if (layout.scaled && withinBudget) {
    Volume asScaled = v;
    asScaled.type = layout.scaledType;
    validateVolumeHeader(asScaled, path + " (as " + scalarTypeName(layout.scaledType) + ", its scl_slope applied)");
  }
  if (!layout.scaled) layout.slope = 1, layout.inter = 0;
  if (!nim->iname) throw Error(path + ": NIfTI header names no image file");
  if (nim->iname_offset < 0) throw Error(path + ": negative NIfTI vox_offset");
  layout.dataFile = nim->iname;
  layout.offset = std::uint64_t(nim->iname_offset) +
                  std::uint64_t(std::max<std::int64_t>(volume, 0)) * v.voxelCount() * bytesPerVoxel(v.type);
  layout.swapped = nim->byteorder != nifti_short_order();
  return layout;
}

Volume readNifti(const std::string& path, std::int64_t volume) {
  const NiftiLayout layout = readNiftiLayout(path, volume, true);
  Volume v = layout.geometry;
  GzFile file(layout.dataFile, "rb");
  file.skip(layout.offset);
  v.data = file.readExactly(v.voxelCount() * bytesPerVoxel(v.type), path);
  if (layout.swapped) swapBytes(v.data.data(), v.voxelCount(), bytesPerVoxel(v.type));

  // Apply scl_slope/scl_inter as nibabel's get_fdata does: the stored numbers become real values.
  if (layout.scaled) {
    Volume real = v.sameGeometry(layout.scaledType);
    for (std::size_t n = 0; n < v.voxelCount(); ++n) real.setValue(n, layout.slope * v.value(n) + layout.inter);
    v = std::move(real);
  }
  return v;
}

void writeNifti(const std::string& path, const Volume& v) {
  require(!endsWith(path, ".hdr"), path + ": isoatlas writes single-file NIfTI (.nii or .nii.gz)");
  nifti_set_debug_level(0);
  const bool needsNifti2 = v.dims[0] > 32767 || v.dims[1] > 32767 || v.dims[2] > 32767;
  const int64_t dims[8] = {3, v.dims[0], v.dims[1], v.dims[2], 1, 1, 1, 1};
  NiftiPtr nim(nifti_make_new_nim(dims, niftiDatatype(v.type), 0));
  if (!nim) throw Error(path + ": nifticlib could not create a header", ErrorKind::Failure);
  nim->nifti_type = needsNifti2 ? NIFTI_FTYPE_NIFTI2_1 : NIFTI_FTYPE_NIFTI1_1;
  nim->dx = nim->pixdim[1] = v.spacing.x;
  nim->dy = nim->pixdim[2] = v.spacing.y;
  nim->dz = nim->pixdim[3] = v.spacing.z;
  nim->xyz_units = NIFTI_UNITS_MM;

  nifti_dmat44 a{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) a.m[r][c] = v.direction.m[r][c] * v.spacing[c];
    a.m[r][3] = v.origin[r];
  }
  a.m[3][3] = 1;
  nim->sform_code = NIFTI_XFORM_SCANNER_ANAT;
  nim->sto_xyz = a;
  nim->sto_ijk = nifti_dmat44_inverse(a);
  nim->qform_code = NIFTI_XFORM_SCANNER_ANAT;
  double qdx, qdy, qdz;
  nifti_dmat44_to_quatern(a, &nim->quatern_b, &nim->quatern_c, &nim->quatern_d, &nim->qoffset_x, &nim->qoffset_y,
                          &nim->qoffset_z, &qdx, &qdy, &qdz, &nim->qfac);
  nim->qto_xyz = a;

  if (nifti_set_filenames(nim.get(), path.c_str(), 0, 1) != 0)
    throw Error(path + ": not a NIfTI file name (use .nii or .nii.gz)");
  nim->data = const_cast<std::byte*>(v.data.data());
  nifti_image_write(nim.get());
  nim->data = nullptr;  // ours, not nifticlib's to free
  // nifti_image_write reports failure only on stderr: read the header back to be sure it landed.
  NiftiPtr check(nifti_image_read(path.c_str(), 0));
  if (!check || check->nx != v.dims[0] || check->ny != v.dims[1] || check->nz != v.dims[2])
    throw Error(path + ": could not write the NIfTI file", ErrorKind::Failure);
}

}  // namespace isoatlas
