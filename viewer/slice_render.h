// renderSlices: three orthogonal world-aligned slices (axial, coronal, sagittal) through a point, side
// by side in one image, intensities windowed between two percentiles. Radiological convention as in
// 3D Slicer and ITK-SNAP: the patient's right is on the image's left, anterior up in axial, superior
// up in coronal and sagittal, anterior to the right in sagittal. An optional mask (same grid) is drawn over in colour.
//   volume:  the scan (any scalar type, any orientation)
//   centre:  world point the three planes pass through (mm, RAS)
//   options: panel size in pixels, percentile window, mask colour
// Returns an RGB image of 3 panels.
#pragma once
#include "core/image.h"
#include "core/volume.h"

namespace isoatlas::viewer {

struct SliceOptions {
  int panelSize = 320;
  double lowPercentile = 1, highPercentile = 99.5;
  const Volume* mask = nullptr;  // voxels > 0 are tinted
  std::uint8_t maskColour[3] = {255, 80, 40};
};

Image renderSlices(const Volume& volume, const Vec3& centre, const SliceOptions& options = {});
Vec3 volumeCentre(const Volume& volume);  // world position of the middle voxel

}  // namespace isoatlas::viewer
