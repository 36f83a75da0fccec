// The pieces of the Python module (module.cpp registers them): volumes as numpy sees them, and the
// stages, each the library call the CLI makes.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "core/volume.h"

namespace isoatlas::python {

namespace py = pybind11;

void bindVolumes(py::module_& m);
void bindStages(py::module_& m);

// A volume from what Python code holds: an isoatlas.Volume, a numpy array (any layout, a scalar type
// the readers take) with its 4x4 affine (identity when None), or anything with `dataobj` and
// `affine` (a nibabel image). Throws Error naming `what` otherwise.
Volume toVolume(const py::object& object, const py::object& affine, const char* what);
// The volume's voxels as a numpy array of shape (x, y, z) sharing its memory; `owner` keeps it alive.
py::array voxelArray(const Volume& volume, const py::object& owner);
// The 4x4 world transform (RAS, mm), as nibabel gives it.
py::array affineOf(const Volume& volume);

}  // namespace isoatlas::python
