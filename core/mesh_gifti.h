// writeGiftiMesh: a triangle mesh as a GIfTI surface (.surf.gii, through libgiftiio), as FreeSurfer's
// mris_convert and Connectome Workbench write one: a NIFTI_INTENT_POINTSET array (float32, n x 3,
// row-major) with an identity coordinate system from NIFTI_XFORM_SCANNER_ANAT to itself (world RAS
// millimetres, the volume's own frame), then a NIFTI_INTENT_TRIANGLE array (int32, m x 3,
// counter-clockwise seen from outside), both base64 of gzip, little-endian. freeview, Workbench,
// nilearn, niivue and nibabel read it. Refuses a mesh with a face of more than three corners. Throws
// Error naming the file; the file appears only when whole.
#pragma once
#include <string>

#include "core/mesh.h"

namespace isoatlas {

void writeGiftiMesh(const std::string& path, const Mesh& mesh);

}  // namespace isoatlas
