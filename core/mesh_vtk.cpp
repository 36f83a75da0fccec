#include "core/mesh_vtk.h"

#include <bit>
#include <cstdint>

#include "core/atomic_file.h"
#include "core/error.h"

namespace isoatlas {
namespace {

// Appends a 32-bit value big-endian, as VTK's legacy BINARY sections hold them.
void appendBigEndian(std::string& out, std::uint32_t bits) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(char((bits >> shift) & 0xFF));
}
void appendFloats(std::string& out, const Vec3& v) {
  for (const double x : {v.x, v.y, v.z}) appendBigEndian(out, std::bit_cast<std::uint32_t>(float(x)));
}

}  // namespace

void writeVtkMesh(const std::string& path, const Mesh& mesh, bool normals, const std::string& space) {
  require(mesh.faceCount() > 0, path + ": refusing to write a mesh with no faces");
  std::string out = "# vtk DataFile Version 4.2\nisoatlas surface SPACE=" + space + "\nBINARY\nDATASET POLYDATA\n";
  out += "POINTS " + std::to_string(mesh.vertexCount()) + " float\n";
  for (const Vec3& p : mesh.positions) appendFloats(out, p);
  out += "\nPOLYGONS " + std::to_string(mesh.faceCount()) + " " + std::to_string(mesh.faceCount() + mesh.faceVertices.size()) + "\n";
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto corners = mesh.face(f);
    appendBigEndian(out, std::uint32_t(corners.size()));
    for (const std::uint32_t v : corners) appendBigEndian(out, v);
  }
  out += "\n";
  if (normals && mesh.normals.size() == mesh.positions.size()) {
    out += "POINT_DATA " + std::to_string(mesh.vertexCount()) + "\nNORMALS Normals float\n";
    for (const Vec3& n : mesh.normals) appendFloats(out, n);
    out += "\n";
  }
  writeFileAtomically(path, out);
}

}  // namespace isoatlas
