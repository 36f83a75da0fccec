// The level set against ITK's: ITK's ThresholdSegmentationLevelSetImageFilter (the threshold speed
// ITK-SNAP's snake mode drives, the benchmarks' peer) segmented the committed phantom to convergence,
// and bench/itk-reference committed its mask (ITK is not in the test build). Ours, on both backends,
// run to convergence from the same seed with the same T, eps and alpha, must agree with it to a Dice
// floor, and stop where ITK's stops: at the mouth of a dim tube, where curvature holds the front back
// (with alpha 0.5 both cross it to the far ball).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "core/volume_io.h"
#include "pipeline/segmentation.h"
#include "tests/gl_context.h"

namespace isoatlas {
namespace {

const std::string kData = std::string(ISOATLAS_SOURCE_DIR) + "/tests/levelset/data/";

double dice(const Volume& a, const Volume& b) {
  std::int64_t both = 0, sa = 0, sb = 0;
  for (std::size_t n = 0; n < a.voxelCount(); ++n) {
    const bool p = a.value(n) > 0, q = b.value(n) > 0;
    both += p && q, sa += p, sb += q;
  }
  return sa + sb ? 2.0 * double(both) / double(sa + sb) : 1.0;
}

// Inside voxels from x = 28 on: the far ball (and the tube's last voxels before it).
std::int64_t farVoxels(const Volume& mask) {
  std::int64_t n = 0;
  for (std::size_t v = 0; v < mask.voxelCount(); ++v) n += mask.value(v) > 0 && std::int64_t(v) % mask.dims[0] >= 28;
  return n;
}

TEST(ItkReference, TheLevelSetAgreesWithItksOnThePhantom) {
  std::ifstream in(kData + "itk_phantom.json");
  const nlohmann::json p = nlohmann::json::parse(in);
  const Volume phantom = readVolume(kData + "itk_phantom.nii.gz"), itk = readVolume(kData + "itk_phantom_itk_mask.nii.gz");
  ASSERT_EQ(itk.voxelCount(), phantom.voxelCount());
  // ITK's front filled the seed's ball (about 3,000 voxels) and stopped short of the far one.
  ASSERT_GT(p["itk"]["voxels"].get<std::int64_t>(), 2500);
  ASSERT_EQ(farVoxels(itk), 0);
  pipeline::SegmentationRequest request;
  request.params = {p["target"].get<float>(), p["width"].get<float>(), p["alpha"].get<float>()};
  for (const auto& s : p["seeds"]) request.seeds.push_back({{s[0].get<double>(), s[1].get<double>(), s[2].get<double>()}, s[3].get<double>()});
  request.maxIterations = 5000;
  for (const levelset::Backend backend : {levelset::Backend::Cpu, levelset::Backend::Gpu}) {
    SCOPED_TRACE(backend == levelset::Backend::Gpu ? "gpu" : "cpu");
    if (backend == levelset::Backend::Gpu) test::glContext();
    request.backend = backend;
    const pipeline::Segmentation ours = pipeline::segmentVolume(phantom, request);
    ASSERT_TRUE(ours.stats.converged);
    EXPECT_GE(dice(ours.mask, itk), 0.99);
    EXPECT_LT(farVoxels(ours.mask), 20) << "the front crossed the tube, where ITK's stopped";
  }
}

}  // namespace
}  // namespace isoatlas
