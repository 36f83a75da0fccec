// MeshSolid: a closed triangle mesh as a DVT solid (solid.h): the signed distance to the mesh,
// negative inside, the side from the parity of a ray's crossings (CGAL's AABB tree for both).
#pragma once
#include <memory>

#include "core/mesh.h"
#include "levelset/dvt/solid.h"

namespace isoatlas::levelset::dvt {

// Throws Error naming `name` unless the mesh is closed triangles.
std::unique_ptr<DistanceSolid> meshSolid(const Mesh& mesh, const std::string& name);

}  // namespace isoatlas::levelset::dvt
