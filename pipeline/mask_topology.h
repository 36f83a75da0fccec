// maskTopology: a mask's topology as its extracted surface has it: marching cubes at 0.5 traces the
// pair (6+, 18) that the topology-preserving level set keeps (extract/marching_cubes.h,
// levelset/simple_point.h), so the surfaces' count (the object's components and its cavities) and
// their Euler number (2 - 2 genus each, summed) are the object's; its components are counted apart
// (a hollow ball and two balls have the same surfaces). Two masks with different figures differ in
// topology; equal figures are what "the same topology" is checked by here.
//   mask  any volume, inside > 0 (uint8 masks and the level set's starts)
#pragma once
#include <cstdint>

#include "core/volume.h"

namespace isoatlas::pipeline {

struct MaskTopology {
  std::int64_t components = 0;  // the object's, 6-connected
  std::int64_t surfaces = 0;    // closed surfaces: the components plus their cavities
  std::int64_t euler = 0;       // the surfaces' Euler characteristic, summed: 2 surfaces - 2 genus
  bool operator==(const MaskTopology&) const = default;
};

MaskTopology maskTopology(const Volume& mask);

}  // namespace isoatlas::pipeline
