// The stages, each the library call the CLI makes (app/): probe, segment (and the steerable
// LevelSet), extract. Long calls release the GIL; progress reaches a Python callable through
// core/progress's observer, which also stops the work on Ctrl-C (KeyboardInterrupt).
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <optional>

#include "pipeline/gpu.h"
#include "pipeline/seed_ball.h"
#include "pipeline/segmentation.h"
#include "pipeline/volume_editing.h"
#include "edit/solids/volume_solid.h"
#include "core/error.h"
#include "core/mapped_nifti.h"
#include "core/progress.h"
#include "extract/extract_surface.h"
#include "levelset/probe.h"
#include "python/bindings.h"

namespace isoatlas::python {
namespace {

std::vector<pipeline::Ball> seedBalls(const std::vector<std::vector<double>>& seeds, const Volume& v) {
  std::vector<pipeline::Ball> balls;
  for (const auto& s : seeds) {
    require(s.size() == 3 || s.size() == 4, "seeds: each is (x, y, z) or (x, y, z, radius) in voxel indices");
    balls.push_back({{s[0], s[1], s[2]}, s.size() == 4 ? s[3] : 3.0});
    require(balls.back().radius >= pipeline::kMinBallRadius && balls.back().radius <= pipeline::kMaxBallRadius,
            "seeds: a radius must lie in [0.5, 1000] voxels");
    pipeline::requireInside(v, balls.back().centre, "seeds");
  }
  return balls;
}

}  // namespace

pipeline::Gpu& gpuFor(const std::string& backend, bool warnOnFallback) {
  require(backend == "gpu" || backend == "cpu" || backend == "auto", "backend=" + backend + ": expected gpu, cpu or auto");
  // Per thread: a GL context is current on one thread at a time, so each Python thread that asks for
  // the GPU (or a render) gets its own, made on its first call and ended with the thread.
  thread_local pipeline::Gpu cpu;  // no context until a render needs one
  thread_local std::optional<pipeline::Gpu> gl;  // the thread's first gpu or auto choice decides, later ones share it
  if (backend == "cpu") return cpu;
  if (!gl) {
    gl.emplace(pipeline::chooseBackend(backend));
    // As the command says it on stderr: auto on a machine whose only GL is a software rasteriser.
    if (warnOnFallback && gl->backend == levelset::Backend::Cpu && PyErr_WarnEx(PyExc_RuntimeWarning, "no GPU: using the CPU backend", 1) != 0)
      throw py::error_already_set();
  }
  return *gl;
}

py::dict toDict(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

namespace {

// A level set steered from Python, with the scan it reads (kept here: the solver holds it by reference).
struct PyLevelSet {
  std::unique_ptr<Volume> source;
  std::unique_ptr<levelset::LevelSet> levelSet;
};

py::array ownedArray(Volume v) {
  const py::object owner = py::cast(std::move(v));
  return voxelArray(owner.cast<const Volume&>(), owner);
}

}  // namespace

void bindStages(py::module_& m) {
  py::class_<PyLevelSet>(m, "LevelSet", "the steerable segmentation (isoatlas view steers the same): seed, step, change T/eps/alpha, read")
      .def(py::init([](const py::object& volume, double target, double width, double alpha, const std::string& backend, const py::object& affine,
                       const std::string& topology) {
             const levelset::SpeedParams params{float(target), float(width), float(alpha)};
             levelset::validateParams(params);
             const levelset::Topology kept = levelset::topologyFor(topology, "topology=");
             PyLevelSet p;
             p.source = std::make_unique<Volume>(toVolume(volume, affine, "LevelSet"));
             p.levelSet = std::make_unique<levelset::LevelSet>(*p.source, params,
                                                               levelset::LevelSetOptions{.backend = gpuFor(backend).backend, .topology = kept});
             return p;
           }), py::arg("volume"), py::arg("target"), py::arg("width"), py::arg("alpha") = 0.5, py::arg("backend") = "auto",
           py::arg("affine") = py::none(), py::arg("topology") = "free")
      .def("add_sphere", [](PyLevelSet& p, const std::vector<double>& centre, double radius, bool add) {
             require(centre.size() == 3, "add_sphere: centre is (x, y, z) in voxel indices");
             pipeline::requireInside(*p.source, {centre[0], centre[1], centre[2]}, "add_sphere: centre");
             p.levelSet->addSphere({centre[0], centre[1], centre[2]}, radius, add);
           }, py::arg("centre"), py::arg("radius") = 3.0, py::arg("add") = true, "a ball (voxel indices, radius in voxels) in or out")
      .def("set_params", [](PyLevelSet& p, std::optional<double> target, std::optional<double> width, std::optional<double> alpha) {
             levelset::SpeedParams q = p.levelSet->params();
             if (target) q.target = float(*target);
             if (width) q.width = float(*width);
             if (alpha) q.alpha = float(*alpha);
             levelset::validateParams(q);
             p.levelSet->setParams(q);
           }, py::arg("target") = py::none(), py::arg("width") = py::none(), py::arg("alpha") = py::none())
      .def("step", [](PyLevelSet& p, int n) {
             require(n >= 0, "step: n must be >= 0");
             py::gil_scoped_release release;
             for (int i = 0; i < n; ++i) p.levelSet->step();
           }, py::arg("n") = 1)
      .def("run", [](PyLevelSet& p, int iterations, bool converge, const py::object& progress) {
             require(iterations > 0, "iterations must be > 0");
             levelset::RunStats stats;
             {
               ProgressToPython report(progress);
               py::gil_scoped_release release;
               Progress bar("segment", std::uint64_t(iterations), "iterations");
               stats = p.levelSet->run({.maxIterations = iterations, .untilConverged = converge,
                                        .progress = [&](int i, std::int64_t) { bar.update(std::uint64_t(i)); }});
             }
             py::dict d;
             d["iterations"] = stats.iterations, d["converged"] = stats.converged, d["seconds"] = stats.seconds;
             return d;
           }, py::arg("iterations") = 1000, py::arg("converge") = true, py::arg("progress") = py::none())
      .def("mask", [](const PyLevelSet& p) { return ownedArray(p.levelSet->mask()); }, "uint8 (x, y, z), 1 inside")
      .def("phi", [](const PyLevelSet& p) { return ownedArray(p.levelSet->phi()); }, "float32 (x, y, z), > 0 inside, in voxels")
      .def_property_readonly("iterations", [](const PyLevelSet& p) { return p.levelSet->iterations(); })
      .def_property_readonly("active_pages", [](const PyLevelSet& p) { return p.levelSet->pages().activePages().size(); })
      .def_property_readonly("backend", [](const PyLevelSet& p) { return p.levelSet->backendName(); });

  m.def("probe", [](const py::object& volume, const std::vector<double>& at, double radius, const py::object& affine) {
        const VolumeArgument argument(volume, affine, "probe");
        const Volume& v = argument.get();
        require(at.size() == 3, "probe: at is (x, y, z) in voxel indices");
        pipeline::requireInside(v, {at[0], at[1], at[2]}, "probe: at");
        const levelset::ProbeResult p = levelset::probeSphere(v, {at[0], at[1], at[2]}, radius);
        py::dict d;
        d["mean"] = p.mean, d["std"] = p.std, d["voxels"] = p.voxels;
        d["target"] = p.suggestedTarget(), d["width"] = p.suggestedWidth();
        return d;
      }, py::arg("volume"), py::arg("at"), py::arg("radius") = 3.0, py::arg("affine") = py::none(),
      "mean and standard deviation in a ball (voxel indices, radius in voxels), and the T and eps they suggest");

  m.def("segment", [](const py::object& volume, const std::vector<std::vector<double>>& seeds, double target, double width, double alpha,
                      const std::string& backend, int iterations, bool converge, bool halfResolutionStart, const py::object& progress,
                      const py::object& affine, const std::string& topology) {
        const levelset::Topology kept = levelset::topologyFor(topology, "topology=");
        // A path is opened as `segment` opens it (an uncompressed NIfTI read in place, page by page);
        // an array, image or Volume is held compactly.
        std::shared_ptr<const VolumeSource> source;
        bool mapped = false;
        if (py::isinstance<py::str>(volume) || py::hasattr(volume, "__fspath__")) {
          require(affine.is_none(), "segment: affine= places an array; a file gives its own");
          const std::string path = py::str(py::module_::import("os").attr("fspath")(volume));
          requireFile(path);
          source = openVolumeSource(path, {}, &mapped);
        } else {
          source = VolumeInMemory::compact(VolumeArgument(volume, affine, "segment").get());
        }
        const Volume& v = source->geometry();
        const levelset::SpeedParams params{float(target), float(width), float(alpha)};
        levelset::validateParams(params);
        require(iterations > 0, "iterations must be > 0");
        require(converge || !halfResolutionStart, "half_resolution_start needs converge=True");
        const std::vector<pipeline::Ball> balls = seedBalls(seeds, v);
        require(!balls.empty(), "segment: give at least one seed");
        pipeline::Gpu& gpu = gpuFor(backend);
        pipeline::Segmentation s;
        {
          ProgressToPython report(progress);
          py::gil_scoped_release release;
          s = pipeline::segmentVolume(source, {.params = params, .seeds = balls, .backend = gpu.backend, .renderer = gpu.renderer,
                                     .maxIterations = iterations, .untilConverged = converge, .readPhi = true,
                                     .halfResolutionStart = halfResolutionStart, .topology = kept});
        }
        // Arrays sharing the Volumes' voxels (the Volumes kept alive as their owners).
        nlohmann::json figures = s.figures();
        figures["volume_read"] = mapped ? "in place (mapped)" : "into memory";
        return py::make_tuple(ownedArray(std::move(s.mask)), ownedArray(std::move(s.phi)), toDict(figures));
      }, py::arg("volume"), py::arg("seeds"), py::arg("target"), py::arg("width"), py::arg("alpha") = 0.5, py::arg("backend") = "auto",
      py::arg("iterations") = 1000, py::arg("converge") = false, py::arg("half_resolution_start") = false, py::arg("progress") = py::none(),
      py::arg("affine") = py::none(), py::arg("topology") = "free",
      "the paged level-set segmentation (isoatlas segment): (mask uint8, phi float32, report), arrays (x, y, z) in the volume's grid; "
      "volume: an array (with affine), a nibabel image, an isoatlas.Volume, or a file's path (an uncompressed NIfTI is then read in "
      "place, page by page as the band reaches it); seeds in "
      "voxel indices; with converge and half_resolution_start, it starts from its solution at half resolution (faster); "
      "topology=\"preserve\" keeps the seeds' topology (one sphere per seed)");

  m.def("edit", [](const py::object& volume, const std::vector<std::pair<std::string, std::string>>& steps, std::optional<std::uint32_t> depth,
                   const std::string& backend, const py::object& affine) {
        pipeline::EditRequest request{.depth = depth};
        for (const auto& [op, shape] : steps) {
          require(op == "union" || op == "subtract", "edit: each step is (\"union\" or \"subtract\", SHAPE), not " + op);
          request.steps.push_back({op == "union" ? edit::dvt::Op::Union : edit::dvt::Op::Subtract, shape});
        }
        Volume segmentation = toVolume(volume, affine, "edit");
        pipeline::EditInput input;
        {
          py::gil_scoped_release release;
          input = pipeline::editInputOf(std::move(segmentation), request);
          pipeline::checkEditBudget(input, request);  // before any GL work, as the command does
        }
        pipeline::Gpu& gpu = gpuFor(backend);
        Volume mask;
        nlohmann::json figures;
        {
          py::gil_scoped_release release;
          const pipeline::EditedTree edited = pipeline::applyEdits(input, request, gpu);
          const edit::dvt::VolumeTree tree = edited.tree->tree();
          figures = edited.figures(tree);
          mask = edit::dvt::sampleMask(tree);
        }
        return py::make_tuple(ownedArray(std::move(mask)), toDict(figures));
      }, py::arg("volume"), py::arg("steps"), py::arg("depth") = py::none(), py::arg("backend") = "auto", py::arg("affine") = py::none(),
      "boolean edits in a dynamic volume tree (isoatlas edit): steps [(\"union\" | \"subtract\", SHAPE)], SHAPE as the command "
      "takes it in world mm (sphere:X,Y,Z,R, box:..., capsule:..., torus:..., mesh:FILE); (mask in the volume's grid, report)");

  m.def("extract", [](const py::object& volume, std::optional<double> iso, bool largest, const std::string& backend, const py::object& affine) {
        const VolumeArgument argument(volume, affine, "extract");
        const Volume& v = argument.get();
        extract::ExtractOptions options{.largestComponents = largest ? 1u : 0u, .backend = gpuFor(backend).backend};
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
