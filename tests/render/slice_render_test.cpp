// Slices show the right anatomy on the right side: radiological convention, windowing, mask tint.
#include <gtest/gtest.h>

#include "render/slice_render.h"
#include "tests/test_util.h"

namespace isoatlas::render {
namespace {

// 21^3 voxels centred on the world origin; voxels with world x > 0 (the patient's right) hold 200.
Volume rightHalfBright() {
  Volume v = Volume::zeros({21, 21, 21}, ScalarType::UInt8);
  v.origin = {-10, -10, -10};
  for (std::int64_t k = 0; k < 21; ++k)
    for (std::int64_t j = 0; j < 21; ++j)
      for (std::int64_t i = 11; i < 21; ++i) v.setValue(v.index(i, j, k), 200);
  return v;
}

TEST(SliceRender, PatientRightIsOnTheImageLeft) {
  const Volume v = rightHalfBright();
  const Image img = renderSlices(v, volumeCentre(v), {.panelSize = 40, .lowPercentile = 0, .highPercentile = 100});
  ASSERT_EQ(img.width, 120);
  ASSERT_EQ(img.height, 40);
  for (int panel = 0; panel < 2; ++panel) {  // axial and coronal both show x
    EXPECT_EQ(img.at(panel * 40 + 5, 20)[0], 255) << "panel " << panel << " left side should be bright";
    EXPECT_EQ(img.at(panel * 40 + 35, 20)[0], 0) << "panel " << panel << " right side should be dark";
  }
}

TEST(SliceRender, MaskIsTinted) {
  const Volume v = rightHalfBright();
  Volume mask = v.sameGeometry(ScalarType::UInt8);
  mask.setValue(mask.index(10, 10, 10), 1);
  const Image img = renderSlices(v, volumeCentre(v), {.panelSize = 21, .lowPercentile = 0, .highPercentile = 100,
                                                      .mask = &mask});
  const std::uint8_t* centre = img.at(10, 10);  // axial panel, the mask voxel
  EXPECT_GT(centre[0], centre[2]);
  const std::uint8_t* away = img.at(2, 2);
  EXPECT_EQ(away[0], away[2]);
}

}  // namespace
}  // namespace isoatlas::render
