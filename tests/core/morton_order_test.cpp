// mortonOrder: the Morton curve's order on points whose codes are known by hand, and ties broken by
// index, so that the order is one whatever the threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "core/distance/morton_order.h"

namespace isoatlas {
namespace {

TEST(MortonOrder, InterleavesTheCoordinatesXFirst) {
  // The corners of a cube: within the box, each coordinate is 0 or all ones, so the code of corner
  // (x, y, z) repeats the bits z y x, 10 times: corners in the order x + 2y + 4z.
  std::vector<Vec3> corners;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) corners.push_back({double(x), double(y), double(z)});
  std::vector<std::size_t> shuffled{5, 2, 7, 0, 3, 6, 1, 4};
  const std::vector<std::uint64_t> keys = mortonOrder(8, [&](std::size_t i) { return corners[shuffled[i]]; });
  ASSERT_EQ(keys.size(), 8u);
  for (std::size_t k = 0; k < 8; ++k) {
    EXPECT_EQ(shuffled[mortonIndex(keys[k])], k);
    std::uint32_t code = 0;
    for (int bit = 0; bit < 10; ++bit) code |= std::uint32_t(k) << (3 * bit);
    EXPECT_EQ(mortonCode(keys[k]), code);
  }
}

TEST(MortonOrder, EveryPointOnceAndTiesByIndex) {
  std::mt19937 random(5);
  std::uniform_int_distribution<int> cell(0, 3);
  std::vector<Vec3> points(20000);
  for (Vec3& p : points) p = {double(cell(random)), double(cell(random)), double(cell(random))};  // many repeats
  const std::vector<std::uint64_t> keys = mortonOrder(points.size(), [&](std::size_t i) { return points[i]; });
  std::vector<bool> seen(points.size(), false);
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const std::uint32_t index = mortonIndex(keys[k]);
    ASSERT_FALSE(seen[index]);
    seen[index] = true;
    if (k > 0) {
      const std::uint32_t before = mortonIndex(keys[k - 1]);
      EXPECT_TRUE(mortonCode(keys[k - 1]) < mortonCode(keys[k]) || (mortonCode(keys[k - 1]) == mortonCode(keys[k]) && before < index));
      // The same point, the same code; another point (a cell apart on this 4 x 4 x 4 grid), another code.
      const Vec3 &a = points[before], &b = points[index];
      EXPECT_EQ(mortonCode(keys[k - 1]) == mortonCode(keys[k]), a.x == b.x && a.y == b.y && a.z == b.z);
    }
  }
  EXPECT_TRUE(mortonOrder(0, [&](std::size_t i) { return points[i]; }).empty());
}

}  // namespace
}  // namespace isoatlas
