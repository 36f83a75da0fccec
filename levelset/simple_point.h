// isSimplePoint: whether the centre voxel of a 3 x 3 x 3 neighbourhood may change side without
// changing the topology of the object {phi > 0}: its components, cavities and tunnels (Bertrand and
// Malandain 1994; Han, Xu and Prince 2003, the topology-preserving level set's test).
//   Connectivity: the pair (6+, 18): the object is 6-connected, the background 18-connected. That is
//   the pair extract/marching_cubes.h traces: an ambiguous face keeps its two inside corners apart
//   (the inside meets across faces only) and joins the outside across it; a cell's two outside
//   corners on a long diagonal stay apart. So the mesh of a segmentation kept this way has the genus
//   the object has.
//   Test: T6+(x, X) = 1 and T18(x, Xbar) = 1, the topological numbers counted over the geodesic
//   neighbourhoods N_6^3(x, X) and N_18^2(x, Xbar) (Bertrand and Malandain's definitions). Neither
//   depends on the centre's own side, so the same test serves a voxel leaving and one joining.
// Input: inside, bit (dz + 1) * 9 + (dy + 1) * 3 + (dx + 1) set where the neighbour at (dx, dy, dz)
//   is inside (bit 13, the centre, is ignored).
// The GLSL twin is levelset/shaders/simple_point.glsl; its masks come from here as defines
// (simplePointDefines), so the two cannot drift.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace isoatlas::levelset {

bool isSimplePoint(std::uint32_t inside);

// The neighbour at (dx, dy, dz) in {-1, 0, 1}^3: its bit in isSimplePoint's input.
constexpr std::uint32_t neighbourBit(int dx, int dy, int dz) { return 1u << ((dz + 1) * 9 + (dy + 1) * 3 + dx + 1); }
// isSimplePoint's input from inside(dx, dy, dz) -> bool over the 26 neighbours (the centre left out).
template <class Inside>
std::uint32_t insideBits(const Inside& inside) {
  std::uint32_t bits = 0;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if ((dx || dy || dz) && inside(dx, dy, dz)) bits |= neighbourBit(dx, dy, dz);
  return bits;
}

// The neighbourhood masks the test is made of, as GLSL defines for simple_point.glsl.
std::vector<std::pair<std::string, std::string>> simplePointDefines();

// The value a voxel refused a change of side is left with (Han et al.: epsilon times its old sign):
// it stays on its side, as close to the front as the step took it, in voxels.
inline constexpr float kHeldOffFront = 0.01f;  // topology.comp gets it as HELD_OFF_FRONT

}  // namespace isoatlas::levelset
