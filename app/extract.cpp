// isoatlas extract: the closed, manifold isosurface of a level set (phi), a mask or a scalar volume.
#include "app/command.h"
#include "app/options.h"
#include "core/error.h"
#include "core/gz_file.h"
#include "core/mesh_io.h"
#include "core/progress.h"
#include "core/volume_io.h"
#include "extract/extract_surface.h"
#include "pipeline/surface_figures.h"

namespace isoatlas::app {

struct ExtractCommandOptions {
  std::string input, output, backend = "auto";
  VolumeReadOptions read;  // --volume, --series
  std::string space = "ras";  // --space
  std::optional<double> iso;
  bool largest = false;
  std::int64_t minComponent = 0;
  int smooth = 0;
};

void addExtractCommand(CLI::App& app, int& exitCode) {
  auto* sub = app.add_subcommand("extract", "closed, manifold marching cubes over a level set, mask or scalar volume");
  auto o = std::make_shared<ExtractCommandOptions>();
  sub->add_option("input", o->input, "a mask, a phi volume (isoatlas segment --phi) or any scalar volume")->required();
  addVolumeReadOptions(*sub, o->read);
  addMeshSpaceOption(*sub, o->space);
  sub->add_option("--iso", o->iso, "isovalue (default: 0.5 for a mask, else the middle of the value range; give 0 for a phi volume)")
      ->check(inRange(-kMaxIntensity, kMaxIntensity));
  sub->add_flag("--largest", o->largest, "keep only the largest component");
  sub->add_option("--min-component", o->minComponent, "drop components of fewer triangles than this (0: keep every one)")
      ->capture_default_str()
      ->check(inRange(0, 1e12));
  sub->add_option("--smooth", o->smooth, "Taubin smoothing iterations (0: none)")->capture_default_str()->check(inRange(0, 1000));
  sub->add_option("--backend", o->backend, "gpu, cpu or auto (the GPU when there is one)")->capture_default_str()->check(backendChoice());
  sub->add_option("-o,--output", o->output, "output mesh (.ply, .off, .obj; .vtk for 3D Slicer and ParaView; .surf.gii for FreeSurfer and Workbench)")->required()->check(outputFile());
  bindAction(*sub, [o](nlohmann::json& r) {
    require(isMeshWritePath(o->output), o->output + ": write the mesh as .ply, .off, .obj, .vtk or .surf.gii");
    requireMeshSpaceFor(o->output, meshSpace(o->space));
    const Volume v = readVolume(o->input, o->read);
    const pipeline::Gpu backend = pipeline::chooseBackend(o->backend);
    const bool gpu = backend.backend == levelset::Backend::Gpu;
    extract::ExtractOptions options{.largestComponents = o->largest ? 1u : 0u, .minComponentTriangles = o->minComponent,
                                    .smoothIterations = o->smooth, .backend = backend.backend};
    if (o->iso) options.iso = float(*o->iso);
    extract::ExtractStats stats;
    const Mesh mesh = extract::extractSurface(v, options, &stats);
    if (mesh.faceCount() == 0)
      throw Error(o->input + ": no surface at iso " + std::to_string(stats.iso) + " (every voxel is on one side)",
                  ErrorKind::Failure);
    writeMesh(o->output, mesh, {.space = meshSpace(o->space)});
    r.update(pipeline::surfaceFigures(mesh, &stats));
    r["backend"] = gpu ? "gpu" : "cpu";
    r["renderer"] = backend.renderer;
    r["gl_contexts"] = gl::Context::made();
    logInfo("extract: " + std::to_string(mesh.faceCount()) + " triangles, " + std::to_string(mesh.vertexCount()) +
            " vertices at iso " + std::to_string(stats.iso) + " -> " + o->output);
    return 0;
  }, exitCode);
}

}  // namespace isoatlas::app
