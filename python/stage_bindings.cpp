// The stages, each the library call the CLI makes (app/): probe, segment (and the steerable
// LevelSet), extract. Long calls release the GIL; progress reaches a Python callable through
// core/progress's observer, which also stops the work on Ctrl-C (KeyboardInterrupt).
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <optional>

#include "app/options.h"
#include "app/segmentation.h"
#include "core/error.h"
#include "core/progress.h"
#include "extract/extract_surface.h"
#include "levelset/probe.h"
#include "python/bindings.h"

namespace isoatlas::python {
namespace {

// The process's GL context, made on the first GPU call and kept (one per process, as the CLI).
app::Gpu& gpuFor(const std::string& backend) {
  static std::optional<app::Gpu> gpu;
  static std::string chosen;
  if (!gpu || chosen != backend) {
    require(!gpu || gpu->backend == levelset::Backend::Cpu || backend == chosen,
            "backend=" + backend + ": this process already runs on the GPU (one GL context per process)");
    gpu.emplace(app::chooseBackend(backend));
    chosen = backend;
  }
  return *gpu;
}

// While alive: core/progress's updates go to `callback(task, fraction)` with the GIL held, and a
// pending Ctrl-C stops the work there (the Python exception propagates out of the stage).
class ProgressToPython {
public:
  explicit ProgressToPython(py::object callback) : callback_(std::move(callback)) {
    Progress::setObserver([this](const std::string& task, double fraction) {
      py::gil_scoped_acquire gil;
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (!callback_.is_none()) callback_(task, fraction);
    });
  }
  ~ProgressToPython() { Progress::setObserver({}); }

private:
  py::object callback_;
};

std::vector<app::Ball> seedBalls(const std::vector<std::vector<double>>& seeds, const Volume& v) {
  std::vector<app::Ball> balls;
  for (const auto& s : seeds) {
    require(s.size() == 3 || s.size() == 4, "seeds: each is (x, y, z) or (x, y, z, radius) in voxel indices");
    balls.push_back({{s[0], s[1], s[2]}, s.size() == 4 ? s[3] : 3.0});
    require(balls.back().radius > 0, "seeds: a radius must be > 0");
    app::requireInside(v, balls.back().centre, "seeds");
  }
  return balls;
}

py::dict toDict(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

py::tuple meshArrays(const Mesh& mesh) {
  py::array_t<double> vertices({py::ssize_t(mesh.vertexCount()), py::ssize_t(3)});
  auto v = vertices.mutable_unchecked<2>();
  for (std::size_t i = 0; i < mesh.vertexCount(); ++i)
    for (int a = 0; a < 3; ++a) v(py::ssize_t(i), a) = mesh.positions[i][a];
  py::array_t<std::int64_t> triangles({py::ssize_t(mesh.faceCount()), py::ssize_t(3)});
  auto t = triangles.mutable_unchecked<2>();
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto c = mesh.face(f);
    require(c.size() == 3, "extract made a face that is not a triangle");
    for (int k = 0; k < 3; ++k) t(py::ssize_t(f), k) = c[std::size_t(k)];
  }
  return py::make_tuple(vertices, triangles);
}

}  // namespace

void bindStages(py::module_& m) {
  m.def("probe", [](const py::object& volume, const std::vector<double>& at, double radius, const py::object& affine) {
        const Volume v = toVolume(volume, affine, "probe");
        require(at.size() == 3, "probe: at is (x, y, z) in voxel indices");
        app::requireInside(v, {at[0], at[1], at[2]}, "probe: at");
        const levelset::ProbeResult p = levelset::probeSphere(v, {at[0], at[1], at[2]}, radius);
        py::dict d;
        d["mean"] = p.mean, d["std"] = p.std, d["voxels"] = p.voxels;
        d["target"] = p.suggestedTarget(), d["width"] = p.suggestedWidth();
        return d;
      }, py::arg("volume"), py::arg("at"), py::arg("radius") = 3.0, py::arg("affine") = py::none(),
      "mean and standard deviation in a ball (voxel indices, radius in voxels), and the T and eps they suggest");

  m.def("segment", [](const py::object& volume, const std::vector<std::vector<double>>& seeds, double target, double width, double alpha,
                      const std::string& backend, int iterations, bool converge, const py::object& progress, const py::object& affine) {
        const Volume v = toVolume(volume, affine, "segment");
        const levelset::SpeedParams params{float(target), float(width), float(alpha)};
        levelset::validateParams(params);
        require(iterations > 0, "iterations must be > 0");
        const std::vector<app::Ball> balls = seedBalls(seeds, v);
        require(!balls.empty(), "segment: give at least one seed");
        app::Gpu& gpu = gpuFor(backend);
        app::Segmentation s;
        {
          ProgressToPython report(progress);
          py::gil_scoped_release release;
          s = app::segmentVolume(v, {.params = params, .seeds = balls, .backend = gpu.backend, .renderer = gpu.renderer,
                                     .maxIterations = iterations, .untilConverged = converge, .readPhi = true});
        }
        // Arrays sharing the Volumes' voxels (the Volumes kept alive as their owners).
        const py::object mask = py::cast(std::move(s.mask)), phi = py::cast(std::move(s.phi));
        return py::make_tuple(voxelArray(mask.cast<const Volume&>(), mask), voxelArray(phi.cast<const Volume&>(), phi),
                              toDict(s.figures()));
      }, py::arg("volume"), py::arg("seeds"), py::arg("target"), py::arg("width"), py::arg("alpha") = 0.5, py::arg("backend") = "auto",
      py::arg("iterations") = 1000, py::arg("converge") = false, py::arg("progress") = py::none(), py::arg("affine") = py::none(),
      "the paged level-set segmentation (isoatlas segment): (mask uint8, phi float32, report), arrays (x, y, z) in the volume's grid; seeds in voxel indices");

  m.def("extract", [](const py::object& volume, std::optional<double> iso, bool largest, const std::string& backend, const py::object& affine) {
        const Volume v = toVolume(volume, affine, "extract");
        const bool gpu = gpuFor(backend).backend == levelset::Backend::Gpu;
        extract::ExtractOptions options{.largestComponent = largest, .gpu = gpu};
        if (iso) options.iso = float(*iso);
        Mesh mesh;
        {
          py::gil_scoped_release release;
          mesh = extract::extractSurface(v, options);
        }
        return meshArrays(mesh);
      }, py::arg("volume"), py::arg("iso") = py::none(), py::arg("largest") = false, py::arg("backend") = "auto",
      py::arg("affine") = py::none(),
      "marching cubes (isoatlas extract): (vertices N x 3 in world mm, triangles M x 3)");
}

}  // namespace isoatlas::python
