// build, Model, load_model, render: the multiresolution model from numpy meshes (the library calls
// `isoatlas build` and `isoatlas render` make), its levels as arrays, pictures as H x W x 3 arrays.
#include <pybind11/stl.h>

#include <filesystem>
#include <optional>

#include "pipeline/model_building.h"
#include "atlas/model_file.h"
#include "atlas/evaluate_levels.h"
#include "atlas/reconstruct.h"
#include "core/error.h"
#include "core/image.h"
#include "core/gl/context.h"
#include "core/gl/resources.h"
#include "python/bindings.h"
#include "render/scene.h"

namespace isoatlas::python {
namespace {

struct PyModel {
  atlas::Model model;
  py::dict figures;
};

}  // namespace

void bindModels(py::module_& m) {
  py::class_<PyModel>(m, "Model", "a multiresolution model: the triquad base mesh and its atlas of geometry-image charts")
      .def("save", [](const PyModel& p, const std::string& path) {
             require(path.ends_with(".isoatlas"), path + ": the model file must end in .isoatlas");
             atlas::writeModel(path, p.model);
           }, py::arg("path"))
      .def("mesh_at_level", [](const PyModel& p, int level) { return meshArrays(atlas::reconstructLevel(p.model.base, p.model.atlas, level)); },
           py::arg("level"), "(vertices, triangles) of the surface with every tile refined to `level` (0: the base mesh's triangles)")
      .def_property_readonly("base_mesh", [](const PyModel& p) { return meshArrays(p.model.base.quadMesh(), 4); },
           "(vertices, quads): the triquad base mesh, one quad a tile, as `isoatlas build --base-only` writes it")
      .def_property_readonly("max_level", [](const PyModel& p) { return atlas::maxLevel(p.model.atlas); })
      .def_property_readonly("chart_size", [](const PyModel& p) { return p.model.chartSize; })
      .def_property_readonly("tiles", [](const PyModel& p) { return p.model.atlas.layout.charts; })
      .def_property_readonly("atlas_positions", [](const PyModel& p) {
             const auto& l = p.model.atlas.layout;
             py::array_t<float> a({py::ssize_t(l.height()), py::ssize_t(l.width()), py::ssize_t(3)});
             std::memcpy(a.mutable_data(), p.model.atlas.positions.data(), p.model.atlas.positions.size() * sizeof(float) * 3);
             return a;
           }, "the atlas's texels (rows, columns, xyz in world mm), zero outside the charts")
      .def_readonly("report", &PyModel::figures, "what `isoatlas build` reports (empty for a loaded model)");

  m.def("build", [](const py::object& vertices, const py::object& triangles, std::optional<double> baseRatio, std::uint32_t chartSize, bool hausdorff,
                    const py::object& progress, std::optional<int> relaxSweeps) {
        pipeline::ModelRequest request{.baseRatio = baseRatio, .chartSize = chartSize, .relaxSweeps = relaxSweeps, .hausdorff = hausdorff};
        pipeline::checkModelRequest(request);
        const Mesh dense = pipeline::prepareModelInput(toMesh(vertices, triangles));
        PyModel p;
        nlohmann::json figures;
        {
          ProgressToPython report(progress);
          py::gil_scoped_release release;
          p.model = pipeline::buildModel(dense, request, figures);
        }
        p.figures = toDict(figures);
        return p;
      }, py::arg("vertices"), py::arg("triangles"), py::arg("base_ratio") = py::none(), py::arg("chart_size") = 33, py::arg("hausdorff") = true,
      py::arg("progress") = py::none(), py::arg("relax_sweeps") = py::none(),
      "the multiresolution model of a closed triangle mesh (isoatlas build)");

  m.def("load_model", [](const std::string& path) {
        requireFile(path);
        return PyModel{atlas::readModel(path), {}};
      }, py::arg("path"));

  m.def("eval", [](const PyModel& p, const py::object& vertices, const py::object& triangles, const std::string& levels, std::size_t samples,
                   const py::object& progress) {
        const Mesh dense = pipeline::prepareModelInput(toMesh(vertices, triangles));
        pipeline::requireDenseOf(p.model, dense, "eval: vertices, triangles");
        const int top = atlas::maxLevel(p.model.atlas);
        const std::vector<int> wanted = pipeline::parseLevels(levels.empty() ? "0-" + std::to_string(top) : levels, top);
        std::vector<atlas::LevelFigures> figures;
        {
          ProgressToPython report(progress);
          py::gil_scoped_release release;
          figures = atlas::evaluateLevels(p.model.base, p.model.atlas, dense, wanted, samples);
        }
        // A list that owns its items (an accessor into a temporary dict would outlive the dict).
        return py::list(toDict(nlohmann::json{{"levels", pipeline::levelFiguresJson(figures)}})["levels"]);
      }, py::arg("model"), py::arg("vertices"), py::arg("triangles"), py::arg("levels") = "", py::arg("samples") = kHausdorffFacePoints,
      py::arg("progress") = py::none(),
      "per level (isoatlas eval): level, vertices, triangles, hausdorff, psnr_db, rms, psnr_rms_db, closed, manifold against the dense mesh; "
      "levels as eval takes them (\"0-10\", \"4\", \"0,2,10\"; default all)");

  m.def("write_png", [](const std::string& path, const py::object& image) {
        require(path.ends_with(".png"), path + ": write_png writes a .png");
        const auto a = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(image);
        require(a && a.ndim() == 3 && (a.shape(2) == 3 || a.shape(2) == 4) && a.shape(0) > 0 && a.shape(1) > 0,
                "write_png: an H x W x 3 (or 4) uint8 array");
        Image out(int(a.shape(1)), int(a.shape(0)), int(a.shape(2)));
        std::memcpy(out.pixels.data(), a.data(), out.pixels.size());
        writePng(path, out);
      }, py::arg("path"), py::arg("image"), "an H x W x 3 picture (render's) as PNG");

  m.def("render", [](const PyModel& p, int width, int height, int cpuLevel, int gpuLevel, bool wireframe,
                     const std::optional<std::vector<double>>& camera) {
        require(width >= 1 && height >= 1 && width <= 8192 && height <= 8192, "size: whole pixels from 1 to 8192");
        require(cpuLevel >= 0 && cpuLevel <= atlas::maxLevel(p.model.chartSize), "cpu_level: 0 .. the chart's finest level");
        require(gpuLevel >= 0, "gpu_level must be >= 0");
        gpuFor("auto", false).needGl();
        render::Scene scene({&p.model});
        render::Camera view = scene.defaultCamera(width, height);
        if (camera) {
          require(camera->size() == 7, "camera: (eye x, y, z, target x, y, z, vertical field of view in degrees)");
          const auto& c = *camera;
          view.eye = {c[0], c[1], c[2]}, view.target = {c[3], c[4], c[5]}, view.fovDegrees = c[6];
          view.check();
        }
        const render::AtlasRenderer renderer;
        const gl::Framebuffer target(width, height);
        render::drawFrame(scene, renderer, {.mode = render::CpuRefinement::Mode::Level, .level = cpuLevel},
                          {.mode = render::GpuRefinement::Mode::Level, .halvings = gpuLevel}, view,
                          {.wireframe = wireframe}, target);
        const Image image = target.readImage();
        py::array_t<std::uint8_t> a({py::ssize_t(height), py::ssize_t(width), py::ssize_t(3)});
        std::memcpy(a.mutable_data(), image.pixels.data(), image.pixels.size());
        return a;
      }, py::arg("model"), py::arg("width") = 800, py::arg("height") = 600, py::arg("cpu_level") = 2, py::arg("gpu_level") = 1,
      py::arg("wireframe") = false, py::arg("camera") = py::none(),
      "the model through the cascade, as `isoatlas render` draws it: an H x W x 3 uint8 array; camera as render's --camera "
      "(eye, target in world mm, vertical field of view in degrees), default the whole model from the front");
}

}  // namespace isoatlas::python
