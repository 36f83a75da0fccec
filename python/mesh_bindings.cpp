// read_mesh, write_mesh, surface_figures: triangle meshes as numpy arrays to and from files, and the
// figures `isoatlas extract` reports of a surface (size, topology, area).
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "core/mesh_io.h"
#include "pipeline/surface_figures.h"
#include "python/bindings.h"

namespace isoatlas::python {

void requireFile(const std::string& path) {
  if (std::filesystem::exists(path)) return;
  PyErr_SetString(PyExc_FileNotFoundError, (path + ": no such file").c_str());
  throw py::error_already_set();
}

py::tuple meshArrays(const Mesh& mesh, std::size_t corners) {
  py::array_t<double> vertices({py::ssize_t(mesh.vertexCount()), py::ssize_t(3)});
  auto v = vertices.mutable_unchecked<2>();
  for (std::size_t i = 0; i < mesh.vertexCount(); ++i)
    for (int a = 0; a < 3; ++a) v(py::ssize_t(i), a) = mesh.positions[i][a];
  py::array_t<std::int64_t> faces({py::ssize_t(mesh.faceCount()), py::ssize_t(corners)});
  auto f = faces.mutable_unchecked<2>();
  for (std::size_t n = 0; n < mesh.faceCount(); ++n) {
    const auto c = mesh.face(n);
    require(c.size() == corners, "a face of " + std::to_string(c.size()) + " corners among faces of " + std::to_string(corners));
    for (std::size_t k = 0; k < corners; ++k) f(py::ssize_t(n), py::ssize_t(k)) = c[k];
  }
  return py::make_tuple(vertices, faces);
}

Mesh toMesh(const py::object& vertices, const py::object& triangles) {
  const auto v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(vertices);
  const auto t = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(triangles);
  require(v && v.ndim() == 2 && v.shape(1) == 3, "vertices: an N x 3 array of positions");
  require(t && t.ndim() == 2 && t.shape(1) == 3, "triangles: an M x 3 array of vertex indices");
  Mesh mesh;
  const auto vv = v.unchecked<2>();
  for (py::ssize_t i = 0; i < v.shape(0); ++i) {
    mesh.positions.push_back({vv(i, 0), vv(i, 1), vv(i, 2)});
    require(std::isfinite(vv(i, 0)) && std::isfinite(vv(i, 1)) && std::isfinite(vv(i, 2)), "vertices: row " + std::to_string(i) + " is not finite");
  }
  const auto tt = t.unchecked<2>();
  for (py::ssize_t f = 0; f < t.shape(0); ++f) {
    for (int k = 0; k < 3; ++k)
      require(tt(f, k) >= 0 && tt(f, k) < v.shape(0), "triangles: row " + std::to_string(f) + " names a vertex that is not there");
    mesh.addFace({std::uint32_t(tt(f, 0)), std::uint32_t(tt(f, 1)), std::uint32_t(tt(f, 2))});
  }
  return mesh;
}

void bindMeshes(py::module_& m) {
  m.def("read_mesh", [](const std::string& path) {
        requireFile(path);
        const Mesh mesh = readMesh(path);
        return meshArrays(mesh.allFacesHave(3) ? mesh : triangulated(mesh));
      }, py::arg("path"), "(vertices N x 3, triangles M x 3) of a .ply, .off, .obj or .stl (polygons split as build splits them: each triangle turning as its polygon)");
  m.def("write_mesh", [](const std::string& path, const py::object& vertices, const py::object& triangles, const std::string& space) {
        const MeshSpace frame = parseMeshSpace(space, "write_mesh");
        const Mesh mesh = toMesh(vertices, triangles);
        py::gil_scoped_release release;
        writeMesh(path, mesh, {.space = frame});  // whole or not at all (core/atomic_file)
      }, py::arg("path"), py::arg("vertices"), py::arg("triangles"), py::arg("space") = "ras", "a .ply (binary), .off, .obj, .vtk (VTK legacy, tagged with its space for 3D Slicer) or .surf.gii (GIfTI), written whole or not at all; space: ras (as read) or lps (x and y negated)");
  m.def("surface_figures", [](const py::object& vertices, const py::object& triangles) {
        const Mesh mesh = toMesh(vertices, triangles);
        nlohmann::json figures;
        {
          py::gil_scoped_release release;
          figures = pipeline::surfaceFigures(mesh);
        }
        return toDict(figures);
      }, py::arg("vertices"), py::arg("triangles"),
      "what isoatlas extract reports of a surface: vertices, triangles, components, closed, manifold, euler, genus, area_mm2");
}

}  // namespace isoatlas::python
