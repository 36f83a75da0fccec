// forEachCodeInShell: the position codes exactly `reach` steps from `centre` along some axis (the
// shell of the (2 reach + 1)^3 cube round it, Chebyshev distance `reach`), within 0 ..
// kLargestPositionCode, never along an axis whose step is 0 (the chart is flat there: every code
// decodes alike). For the quantiser's nudges (separate_codes.h, unfold_codes.h), which try the codes
// nearest a texel's own first.
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>

#include "atlas/quantised_atlas.h"

namespace isoatlas::atlas {

template <class Visit>  // void(const std::array<std::uint16_t, 3>& code)
void forEachCodeInShell(const QuantisedChart& chart, const std::array<std::uint16_t, 3>& centre, int reach, const Visit& visit) {
  for (int dz = -reach; dz <= reach; ++dz)
    for (int dy = -reach; dy <= reach; ++dy)
      for (int dx = -reach; dx <= reach; ++dx) {
        if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != reach) continue;  // this shell only
        const int d[3] = {dx, dy, dz};
        std::array<std::uint16_t, 3> code{};
        bool valid = true;
        for (int a = 0; a < 3; ++a) {
          const int v = int(centre[a]) + d[a];
          valid &= (d[a] == 0 || chart.step[a] > 0) && v >= 0 && v <= int(kLargestPositionCode);
          code[a] = std::uint16_t(std::clamp(v, 0, int(kLargestPositionCode)));
        }
        if (valid) visit(code);
      }
}

}  // namespace isoatlas::atlas
