// The pieces of the Python module (module.cpp registers them): volumes as numpy sees them, and the
// stages, each the library call the CLI makes.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

#include "pipeline/gpu.h"
#include "core/mesh.h"
#include "core/progress.h"
#include "core/volume.h"

namespace isoatlas::python {

namespace py = pybind11;

void bindVolumes(py::module_& m);
void bindStages(py::module_& m);
void bindModels(py::module_& m);
void bindMeshes(py::module_& m);

// A volume from what Python code holds: an isoatlas.Volume, a numpy array (any layout, a scalar type
// the readers take) with its 4x4 affine (identity when None), or anything with `dataobj` and
// `affine` (a nibabel image). Throws Error naming `what` otherwise.
Volume toVolume(const py::object& object, const py::object& affine, const char* what);
// A volume argument read in place: an isoatlas.Volume is used as it is (no copy of its voxels), anything
// else toVolume takes is converted once. Keeps the Python object alive while it lives.
class VolumeArgument {
public:
  VolumeArgument(const py::object& object, const py::object& affine, const char* what);
  const Volume& get() const { return *volume_; }

private:
  py::object object_;
  std::optional<Volume> converted_;
  const Volume* volume_ = nullptr;
};

// The volume's voxels as a numpy array of shape (x, y, z) sharing its memory; `owner` keeps it alive.
py::array voxelArray(const Volume& volume, const py::object& owner);
// The 4x4 world transform (RAS, mm), as nibabel gives it.
py::array affineOf(const Volume& volume);

// (vertices N x 3 float64, faces M x corners int64) of a mesh whose faces all have `corners` corners.
py::tuple meshArrays(const Mesh& mesh, std::size_t corners = 3);
// A triangle mesh from (N x 3 positions, M x 3 vertex indices); Error naming the bad row otherwise.
Mesh toMesh(const py::object& vertices, const py::object& triangles);
// FileNotFoundError (Python's own, as open() raises it) unless `path` exists.
void requireFile(const std::string& path);
// A report as a Python dict.
py::dict toDict(const nlohmann::json& json);
// This thread's backend and GL context, made on its first GPU call and kept until the thread ends (one
// per thread: a context is current on one thread at a time, so two threads' GPU calls each need their
// own; a GPU LevelSet is stepped on the thread that made it): "gpu", "cpu" or "auto"; auto without a
// GPU warns (RuntimeWarning) that it runs on the CPU, unless the caller only wants the context (renders).
pipeline::Gpu& gpuFor(const std::string& backend, bool warnOnFallback = true);

// While alive: core/progress's updates go to `callback(task, fraction)` with the GIL held, and a
// pending Ctrl-C stops the work there (KeyboardInterrupt propagates out of the stage).
class ProgressToPython {
public:
  explicit ProgressToPython(py::object callback)
      : callback_(std::move(callback)), observer_([this](const std::string& task, double fraction) {
          py::gil_scoped_acquire gil;
          if (PyErr_CheckSignals() != 0) throw py::error_already_set();
          if (!callback_.is_none()) callback_(task, fraction);
        }) {}
  ProgressToPython(const ProgressToPython&) = delete;
  ProgressToPython& operator=(const ProgressToPython&) = delete;

private:
  py::object callback_;
  ProgressObserver observer_;  // this thread's, for the call's work (made on this thread)
};

}  // namespace isoatlas::python
