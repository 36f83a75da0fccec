// renderSlices: three orthogonal world-aligned slices (axial, coronal, sagittal) through a point, side
// by side in one image, intensities windowed between two percentiles. Radiological convention as in
// 3D Slicer and ITK-SNAP: the patient's right is on the image's left, anterior up in axial, superior
// up in coronal and sagittal, anterior to the right in sagittal. Optional overlays, as ITK-SNAP's snake
// mode shows them: a mask tinted, a level set's contour (where phi changes sign), the speed's data
// term eps - |I - T| (positive and negative in two colours), and a crosshair at the slice point.
//   volume:  the scan (any scalar type, any orientation)
//   centre:  world point the three planes pass through (mm, RAS)
//   options: panel size in pixels, window, overlays
// Returns an RGB image of 3 panels, each panelSize x panelSize; SliceLayout maps its pixels to the
// world and back (for the mouse).
#pragma once
#include <array>
#include <functional>
#include <optional>

#include "core/image.h"
#include "core/volume.h"
#include "levelset/level_set.h"
#include "levelset/speed.h"

namespace isoatlas::render {

struct IntensityWindow {
  double low = 0, high = 1;  // drawn black and white
};
// The window between two percentiles of (a strided sample of) the volume's values.
IntensityWindow percentileWindow(const Volume& volume, double lowPercentile, double highPercentile);

// phi at voxel (i, j, k) of the volume's grid (> 0 inside), e.g. read from a level set's pages.
using VoxelField = std::function<float(std::int64_t i, std::int64_t j, std::int64_t k)>;
// A level set's phi voxel by voxel from its pool (the GPU's read back once): valid until the level
// set is next used.
VoxelField pagedField(const levelset::LevelSet& levelSet);

struct SliceOptions {
  int panelSize = 320;
  double lowPercentile = 1, highPercentile = 99.5;
  const Volume* mask = nullptr;  // voxels > 0 are tinted
  std::uint8_t maskColour[3] = {255, 80, 40};
  std::optional<IntensityWindow> window;          // instead of the percentiles (a caller drawing often computes it once)
  VoxelField phi;                                 // the contour, trilinear between voxel centres
  const levelset::SpeedParams* speed = nullptr;   // tint eps - |I - T|: positive blue, negative red
  bool crosshair = false;                         // lines through `centre`
};

inline constexpr std::uint8_t kContourColour[3] = {255, 225, 0};

// Panels 0, 1, 2: axial, coronal, sagittal; pixel (px, py) of a panel, its top left corner (0, 0),
// pixel centres at +0.5.
class SliceLayout {
public:
  SliceLayout(const Volume& volume, const Vec3& centre, int panelSize);
  int panelSize() const { return size_; }
  Vec3 world(int panel, double px, double py) const;  // on the panel's plane through the centre
  // The panel pixel a world point projects to (along the panel's normal).
  std::array<double, 2> pixel(int panel, const Vec3& world) const;

private:
  struct Plane {
    int right, up;
    double rightSign;
  };
  static constexpr Plane kPlanes[3] = {{0, 1, -1}, {0, 2, -1}, {1, 2, 1}};  // axial (x,y), coronal (x,z), sagittal (y,z)
  Vec3 centre_, mid_;
  double mmPerPixel_[3];
  int size_;
};

Image renderSlices(const Volume& volume, const Vec3& centre, const SliceOptions& options = {});
Vec3 volumeCentre(const Volume& volume);  // world position of the middle voxel

}  // namespace isoatlas::render
