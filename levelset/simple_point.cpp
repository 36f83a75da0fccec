#include "levelset/simple_point.h"

#include <cstdio>

namespace isoatlas::levelset {
namespace {

// Bit i = x + 3 y + 9 z of the 3 x 3 x 3 cube, (x, y, z) = (dx, dy, dz) + 1.
constexpr std::uint32_t cubeWhere(bool (*keep)(int, int, int)) {
  std::uint32_t m = 0;
  for (int i = 0; i < 27; ++i)
    if (keep(i % 3, i / 3 % 3, i / 9)) m |= 1u << i;
  return m;
}
constexpr int offAxes(int x, int y, int z) { return (x != 1) + (y != 1) + (z != 1); }
constexpr std::uint32_t kX0 = cubeWhere([](int x, int, int) { return x == 0; });
constexpr std::uint32_t kX2 = cubeWhere([](int x, int, int) { return x == 2; });
constexpr std::uint32_t kY0 = cubeWhere([](int, int y, int) { return y == 0; });
constexpr std::uint32_t kY2 = cubeWhere([](int, int y, int) { return y == 2; });
constexpr std::uint32_t kZ0 = cubeWhere([](int, int, int z) { return z == 0; });
constexpr std::uint32_t kZ2 = cubeWhere([](int, int, int z) { return z == 2; });
constexpr std::uint32_t kN6 = cubeWhere([](int x, int y, int z) { return offAxes(x, y, z) == 1; });    // N6*
constexpr std::uint32_t kN18 = cubeWhere([](int x, int y, int z) { return offAxes(x, y, z) == 1 || offAxes(x, y, z) == 2; });  // N18*
constexpr std::uint32_t kN26 = cubeWhere([](int x, int y, int z) { return offAxes(x, y, z) > 0; });    // N26*

// m with each voxel's neighbours along one axis added (within the cube).
std::uint32_t alongX(std::uint32_t m) { return m | ((m & ~kX2) << 1) | ((m & ~kX0) >> 1); }
std::uint32_t alongY(std::uint32_t m) { return m | ((m & ~kY2) << 3) | ((m & ~kY0) >> 3); }
std::uint32_t alongZ(std::uint32_t m) { return m | ((m & ~kZ2) << 9) | ((m & ~kZ0) >> 9); }
// m with its 6- or 18-neighbours added: the offsets with one, or at least one, coordinate 0.
std::uint32_t grow6(std::uint32_t m) { return alongX(m) | alongY(m) | alongZ(m); }
std::uint32_t grow18(std::uint32_t m) { return alongX(alongY(m)) | alongX(alongZ(m)) | alongY(alongZ(m)); }

// Components of `set` under 6- or 18-adjacency, counted up to 2.
template <std::uint32_t (*Grow)(std::uint32_t)>
int componentsUpToTwo(std::uint32_t set) {
  int count = 0;
  while (set && count < 2) {
    std::uint32_t part = set & (~set + 1u);  // its lowest voxel
    for (std::uint32_t next = Grow(part) & set; next != part; next = Grow(part) & set) part = next;
    set &= ~part;
    ++count;
  }
  return count;
}

}  // namespace

bool isSimplePoint(std::uint32_t inside) {
  // T6+(x, X): the 6-components of N_6^3(x, X): X's face neighbours, the edge neighbours 6-adjacent
  // to one of them, and the corners 6-adjacent to one of those.
  const std::uint32_t object = inside & kN26;
  std::uint32_t near = object & kN6;
  near |= grow6(near) & object & kN18;
  near |= grow6(near) & object;
  if (componentsUpToTwo<grow6>(near) != 1) return false;
  // T18(x, Xbar): the 18-components of N_18^2(x, Xbar): the background's face and edge neighbours and
  // the corners 18-adjacent to one of them.
  const std::uint32_t background = ~inside & kN26;
  std::uint32_t around = background & kN18;
  around |= grow18(around) & background;
  return componentsUpToTwo<grow18>(around) == 1;
}

std::vector<std::pair<std::string, std::string>> simplePointDefines() {
  auto hex = [](std::uint32_t m) {
    char s[16];
    std::snprintf(s, sizeof s, "0x%07xu", m);
    return std::string(s);
  };
  return {{"CUBE_X0", hex(kX0)}, {"CUBE_X2", hex(kX2)}, {"CUBE_Y0", hex(kY0)}, {"CUBE_Y2", hex(kY2)},
          {"CUBE_Z0", hex(kZ0)}, {"CUBE_Z2", hex(kZ2)}, {"CUBE_N6", hex(kN6)}, {"CUBE_N18", hex(kN18)},
          {"CUBE_N26", hex(kN26)}};
}

}  // namespace isoatlas::levelset
