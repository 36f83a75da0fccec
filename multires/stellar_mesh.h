// StellarMesh: the halfedge triangle mesh the simplifier and the stellar operators work on (OpenMesh,
// double precision, with status flags so removed elements stay in place until compaction).
#pragma once
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "core/mesh.h"

namespace isoatlas::multires {

struct StellarTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::PrevHalfedge);
  FaceAttributes(OpenMesh::Attributes::Status);
};
using StellarMesh = OpenMesh::TriMesh_ArrayKernelT<StellarTraits>;
using VertexH = OpenMesh::VertexHandle;
using HalfedgeH = OpenMesh::HalfedgeHandle;
using EdgeH = OpenMesh::EdgeHandle;
using FaceH = OpenMesh::FaceHandle;

inline Vec3 toVec3(const OpenMesh::Vec3d& p) { return {p[0], p[1], p[2]}; }
inline OpenMesh::Vec3d toPoint(const Vec3& p) { return {p[0], p[1], p[2]}; }

// Builds the halfedge mesh of a triangle mesh. Vertex i and face f keep their indices. Throws
// Error(BadInput) naming `where` unless the mesh is an oriented 2-manifold of triangles.
StellarMesh toStellarMesh(const Mesh& mesh, const std::string& where);

// The mesh's live vertices and faces, renumbered in order.
Mesh toMesh(const StellarMesh& mesh);

}  // namespace isoatlas::multires
