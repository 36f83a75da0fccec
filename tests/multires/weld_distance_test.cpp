// weldDistance2 against distances worked out by hand on a flat fan of two faces.
#include <gtest/gtest.h>

#include <vector>

#include "multires/weld_distance.h"

namespace isoatlas::multires {
namespace {

// The fan (0,0,0) -> (1,0,0), (0,1,0), (-1,0,0): two faces in z = 0, laid flat as they are, with
// one new spoke to (0,1,0).
FanPoint flat(double x, double y, double z = 0) { return {{x, y, z}, {x, y}}; }
const FanPoint kApex = flat(0, 0);
const std::vector<FanPoint> kRim{flat(1, 0), flat(0, 1), flat(-1, 0)};
constexpr double kNoBound = 1e300;

TEST(WeldDistance, DenseVerticesAboveTheFanGiveTheirHeight) {
  const double h = 0.05;
  // Over both centroids and the spoke's midpoint: each is h from its image and h from a sample.
  std::vector<FanPoint> dense{flat(1.0 / 3, 1.0 / 3, h), flat(-1.0 / 3, 1.0 / 3, h), flat(0, 0.5, h)};
  EXPECT_NEAR(weldDistance2(kApex, kRim, dense, kNoBound), h * h, 1e-15);
  dense.push_back(flat(0.1, 0.1, -3 * h));  // one farther below a face
  EXPECT_NEAR(weldDistance2(kApex, kRim, dense, kNoBound), 9 * h * h, 1e-15);
  dense.push_back(flat(2, 0));  // beyond the rim (rounding): imaged on the corner (1,0,0)
  EXPECT_NEAR(weldDistance2(kApex, kRim, dense, kNoBound), 1.0, 1e-15);
}

TEST(WeldDistance, ImagesFollowTheParametrisationNotTheNearestFace) {
  // On the first face in space, but parametrised at the second face's centroid.
  const std::vector<FanPoint> dense{{{1.0 / 3, 1.0 / 3, 0}, {-1.0 / 3, 1.0 / 3}}};
  EXPECT_NEAR(weldDistance2(kApex, kRim, dense, kNoBound), 4.0 / 9, 1e-15);
}

TEST(WeldDistance, AFaceFarFromEveryDenseVertexCounts) {
  // Only one dense vertex, on the first face's centroid: the second face's centroid (-1/3, 1/3) is
  // nearest the apex (2/9 squared), the spoke's midpoint (0, 1/2) nearest that vertex (5/36).
  const std::vector<FanPoint> dense{flat(1.0 / 3, 1.0 / 3)};
  EXPECT_NEAR(weldDistance2(kApex, kRim, dense, kNoBound), 2.0 / 9, 1e-15);
}

TEST(WeldDistance, StopsOnceTheBoundIsReached) {
  // 0.25 from the first vertex, 1 from the second: a bound of 0.2 is known to be reached at the
  // first, so the answer is at least the bound but short of the exact 1.
  const std::vector<FanPoint> dense{flat(0.2, 0.1, 0.5), flat(0.1, 0.1, 1)};
  EXPECT_NEAR(weldDistance2(kApex, kRim, dense, kNoBound), 1.0, 1e-15);
  const double stopped = weldDistance2(kApex, kRim, dense, 0.2);
  EXPECT_GE(stopped, 0.2);
  EXPECT_LT(stopped, 1.0);
  EXPECT_GE(weldDistance2(kApex, kRim, dense, 1.0), 1.0);
}

}  // namespace
}  // namespace isoatlas::multires
