// MeshSolid: a closed triangle mesh as a DVT solid (solid.h): the signed distance to the mesh,
// negative inside (CGAL's AABB tree). The side comes from the closest point's pseudonormal
// (mesh_sign.h) where the mesh is consistently oriented, else, and where that cannot tell, from the
// parity of a ray's crossings.
#pragma once
#include <memory>

#include "core/mesh.h"
#include "edit/solids/solid.h"

namespace isoatlas::edit::dvt {

// Throws Error naming `name` unless the mesh is closed triangles.
std::unique_ptr<DistanceSolid> meshSolid(const Mesh& mesh, const std::string& name);

}  // namespace isoatlas::edit::dvt
