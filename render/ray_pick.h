// rayPick: where a ray first meets a triangle mesh (Moller-Trumbore on every triangle; for a mouse
// click on what a renderer captured, not for many rays).
//   mesh: triangles (as the renderers capture them; other faces are not looked at)
//   origin, direction: the ray (direction need not be unit)
// Returns the hit point, or nothing when the ray misses.
#pragma once
#include <optional>

#include "core/mesh.h"

namespace isoatlas::render {

std::optional<Vec3> rayPick(const Mesh& mesh, const Vec3& origin, const Vec3& direction);

}  // namespace isoatlas::render
