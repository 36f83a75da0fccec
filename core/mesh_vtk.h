// writeVtkMesh: a mesh as a VTK legacy file (.vtk, "vtk DataFile Version 4.2", BINARY, DATASET
// POLYDATA), the format 3D Slicer, ParaView and VTK read. Points are float32, polygons int32, both
// big-endian as the format requires, and the vertex normals (when the mesh has them) as POINT_DATA
// NORMALS. The title line carries "SPACE=RAS" (or LPS, with --space lps): isoatlas's world is
// millimetres in RAS (core/volume.h), and 3D Slicer takes a model file without a tag as LPS.
// Throws Error naming the file when it cannot be written; the file appears only when whole.
#pragma once
#include <string>

#include "core/mesh.h"

namespace isoatlas {

// space: the tag, "RAS" or "LPS" (the caller has put the coordinates in that frame).
void writeVtkMesh(const std::string& path, const Mesh& mesh, bool normals = true, const std::string& space = "RAS");

}  // namespace isoatlas
