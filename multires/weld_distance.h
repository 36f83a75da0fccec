// weldDistance2: how far a weld moves the surface, measured both ways between the fan the weld leaves
// and the dense vertices it maps again: each dense vertex to its image on the fan (where the
// parametrisation will put it, so at least its distance to the fan), and each new face's centroid
// and each new spoke's midpoint to the nearest dense vertex. A local proxy for the symmetric
// Hausdorff distance a base mesh is judged by, where the quadric measures a mean.
#pragma once
#include <span>

#include "core/vec.h"
#include "multires/vec2.h"

namespace isoatlas::multires {

// A vertex in space and in the ring's flat map (the exponential map the weld parametrises by).
struct FanPoint {
  Vec3 position;
  Vec2 plane;
};

// Inputs: the fan (apex, rim[i], rim[i + 1]) for i + 1 < rim.size(), counter-clockwise in the plane,
// whose first and last spokes are sides of the ring already (only the inner ones are new); `dense`,
// the dense vertices the weld maps again, each imaged through the fan face holding it in the plane
// (the apex and the rim's corners count as dense vertices too); `bound`, a squared distance past
// which the exact figure does not matter.
// Output: the largest squared distance, or some value >= bound as soon as it is known to reach it
// (infinity for a fan whose faces are all flat in the plane).
double weldDistance2(const FanPoint& apex, std::span<const FanPoint> rim, std::span<const FanPoint> dense,
                     double bound);

}  // namespace isoatlas::multires
