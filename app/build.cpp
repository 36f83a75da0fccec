// isoatlas build: the multiresolution model of a triangle mesh: stellar simplification with local
// parametrisation, the triquad base mesh by max-weight matching, one geometry-image chart per tile
// packed into an atlas, written as one .isoatlas file.
#include <filesystem>
#include <limits>

#include "app/command.h"
#include "app/options.h"
#include "pipeline/model_building.h"
#include "core/error.h"
#include "core/mesh_io.h"

namespace isoatlas::app {

void addBuildCommand(CLI::App& app, int& exitCode) {
  auto* sub = app.add_subcommand("build", "multiresolution model of a triangle mesh: base mesh and atlas of charts");
  auto o = std::make_shared<pipeline::ModelRequest>();
  auto input = std::make_shared<std::string>(), output = std::make_shared<std::string>();
  auto baseOnly = std::make_shared<std::string>(), previews = std::make_shared<std::string>();
  auto chart = std::make_shared<int>(int(o->chartSize));
  auto noHausdorff = std::make_shared<bool>(false);
  sub->add_option("mesh", *input, "a 2-manifold mesh (.off, .ply, .obj, .stl), closed or with boundaries")->required();
  sub->add_option("-o,--output", *output, "the model file (.isoatlas)")->check(outputFile());
  auto* ratio = sub->add_option("--base-ratio", o->baseRatio,
                  "base vertices as a fraction of the dense ones (default: 2 % up to 1000 vertices, at least 1 %; a mesh of at most 100 vertices is its own base)")
      ->check(inRange(1e-6, 1));
  auto* vertices = sub->add_option("--base-vertices", o->baseVertices, "base vertex count (instead of --base-ratio), at least 4")
      ->check(inRange(4, 1e9));
  vertices->excludes(ratio);
  sub->add_option("--max-error", o->maxError, "never weld where the quadric RMS distance exceeds this (mm; 0: no bound)")
      ->capture_default_str()
      ->check(inRange(0, kMaxMillimetres));
  sub->add_option("--chart", *chart, "chart size in texels per side, 2^k + 1")
      ->capture_default_str()
      ->check(inRange(3, multires::kMaxChartSize));
  sub->add_option("--relax-sweeps", o->relaxSweeps,
                  "sweeps moving the texels over each tile to follow the surface's bending (0: a uniform grid per tile; "
                  "default 8, and 0 for a mesh that is its own base)")
      ->check(inRange(0, 1000));
  sub->add_flag("--keep-dense", o->keepDense, "keep the dense mesh and its parametrisation in the model");
  sub->add_option("--previews", *previews, "write position_atlas.png, normal_atlas.png and backfacing_atlas.png into this folder");
  sub->add_option("--base-only", *baseOnly, "also write the triquad base mesh as an OBJ of quads")->check(outputFile());
  sub->add_flag("--no-hausdorff", *noHausdorff, "skip measuring the base mesh's Hausdorff distance");
  bindAction(*sub, [=](nlohmann::json& r) {
    require(!output->empty() || !baseOnly->empty(), "build: give -o MODEL.isoatlas, --base-only BASE.obj, or both");
    require(previews->empty() || !output->empty(), "--previews draws the model's atlas: give -o MODEL.isoatlas too");
    require(output->empty() || output->ends_with(".isoatlas"), *output + ": the model file must end in .isoatlas");
    require(baseOnly->empty() || baseOnly->ends_with(".obj"), *baseOnly + ": --base-only writes an .obj");
    require(*chart > 0, "--chart must be 2^k + 1 between 3 and " + std::to_string(multires::kMaxChartSize) + " (e.g. 33)");
    pipeline::ModelRequest request = *o;
    request.chartSize = std::uint32_t(*chart);
    request.hausdorff = !*noHausdorff;
    pipeline::checkModelRequest(request);
    const Mesh dense = pipeline::prepareModelInput(readMesh(*input));
    const atlas::Model model = pipeline::buildModel(dense, request, r);
    if (!baseOnly->empty()) writeMesh(*baseOnly, model.base.quadMesh(), {.binary = false, .normals = false});
    if (!output->empty()) {
      pipeline::AtlasPreviewPaths pictures;
      if (!previews->empty()) {
        std::filesystem::create_directories(*previews);
        const std::filesystem::path dir(*previews);
        pictures = {(dir / "position_atlas.png").string(), (dir / "normal_atlas.png").string(), (dir / "backfacing_atlas.png").string()};
      }
      pipeline::writeModelFiles(model, *output, pictures, r);
    }
    return 0;
  }, exitCode);
}

}  // namespace isoatlas::app
