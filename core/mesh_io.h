// Reading and writing meshes through OpenMesh's readers and writers: OFF (ASCII; binary OFF is
// refused), PLY (ASCII and binary), OBJ (polygons kept, quads stay quads) and STL (read only). Faces
// arrive exactly as the file lists them, without OpenMesh's connectivity repairs, so a non-manifold
// file is seen as it is (see analyzeTopology) instead of being silently split. Throws
// isoatlas::Error naming the file.
#pragma once
#include <string>

#include "core/mesh.h"

namespace isoatlas {

bool isMeshPath(const std::string& path);       // what readMesh reads: .off .ply .obj .stl
bool isMeshWritePath(const std::string& path);  // what writeMesh writes: .off .ply .obj .vtk .gii

// Rejects missing files, unreadable content, counts larger than the file can hold, face indices out
// of range, faces of fewer than three corners, non-finite coordinates and meshes with no faces.
Mesh readMesh(const std::string& path);

// The world frame a mesh file's coordinates are in. isoatlas works in RAS (core/volume.h); LPS (x and
// y negated, a half turn about z, so the triangles keep their winding) is what 3D Slicer assumes for a
// model file without a coordinate tag, and what ITK and DICOM use.
enum class MeshSpace { Ras, Lps };
// "ras" or "lps" (as --space and Python's space= take it); throws Error naming `where` otherwise.
MeshSpace parseMeshSpace(const std::string& text, const std::string& where);
// A GIfTI surface declares its points world RAS (mesh_gifti.h): Error (bad input) naming the file for
// a .gii asked for in LPS. writeMesh checks it; commands call it before their work.
void requireMeshSpaceFor(const std::string& path, MeshSpace space);

struct MeshWriteOptions {
  bool binary = true;   // PLY only
  bool normals = true;  // written when the mesh has them (PLY, OFF, OBJ, VTK)
  MeshSpace space = MeshSpace::Ras;
};
// .off .ply .obj through OpenMesh; .vtk as VTK legacy with its SPACE tag (core/mesh_vtk.h); .gii
// (.surf.gii) as a GIfTI surface of triangles (core/mesh_gifti.h).
void writeMesh(const std::string& path, const Mesh& mesh, MeshWriteOptions options = {});

// Throws Error("<where>: not 2-manifold: <first problem>") unless the mesh is a 2-manifold.
void requireManifold(const Mesh& mesh, const std::string& where);

}  // namespace isoatlas
