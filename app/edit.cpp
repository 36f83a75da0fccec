// isoatlas edit: boolean brush and mesh edits of a segmentation in a dynamic volume tree.
#include <algorithm>

#include "app/command.h"
#include "pipeline/surface_figures.h"
#include "app/options.h"
#include "pipeline/volume_editing.h"
#include "core/error.h"
#include "core/gz_file.h"
#include "core/mesh_io.h"
#include "core/progress.h"
#include "core/volume_io.h"
#include "extract/extract_surface.h"
#include "edit/dvt/dvt_file.h"
#include "edit/dvt/gpu_tree_passes.h"
#include "edit/solids/volume_solid.h"
#include "render/dvt_render.h"

namespace isoatlas::app {
namespace dvt = edit::dvt;
namespace {

// A mesh is extracted on the input's voxels, or finer for a finer edit: at most one halving more
// (8 times the voxels).
std::uint32_t meshSamplingDepth(const dvt::TreeFrame& frame, std::uint32_t editDepth) {
  return std::clamp(editDepth, frame.voxelDepth(), frame.voxelDepth() + 3);
}

// Refuses, before any work, an output volume (the mask, or the field a mesh is extracted from) past
// the volume size limit: a saved tree's or a mesh's box can be far larger than anything meant to be
// sampled densely.
void checkOutputGrid(const std::string& output, const Volume& header) {
  try {
    validateVolumeHeader(header, output);
  } catch (const Error& e) {
    throw Error(std::string(e.what()) + "; write a tree (.dvt) or choose a smaller --depth");
  }
}

}  // namespace

struct EditCommandOptions {
  std::string input, output, backend = "auto", space = "ras";
  std::optional<std::uint32_t> depth;
  std::shared_ptr<std::vector<pipeline::EditStep>> steps = std::make_shared<std::vector<pipeline::EditStep>>();
  bool flat = false;
  int collapseEvery = 0;
  std::string render, renderMode = "raycast";
  std::vector<int> size{800, 600};
  std::uint64_t nodeLimit = dvt::TreeOptions{}.nodeLimit;
};

void addEditCommand(CLI::App& app, int& exitCode) {
  auto* sub = app.add_subcommand("edit", "boolean brush and mesh edits of a segmentation in a dynamic volume tree");
  auto o = std::make_shared<EditCommandOptions>();
  sub->add_option("input", o->input, "a mask or phi volume, a closed mesh (.ply/.off/.obj/.stl) or a tree (.dvt)")->required();
  sub->add_option("--depth", o->depth, "tree depth of the edits (3 per halving of the voxels; default: the input's voxels, 24 for a mesh)")
      ->check(inRange(1, dvt::kMaxDepth));
  addEditStepOptions(*sub, o->steps);
  sub->add_flag("--flat", o->flat, "rasterise every shape at the full depth (no hierarchical rasterisation)");
  sub->add_option("--collapse-every", o->collapseEvery, "also collapse after every K writes (the input's conversion is the first; the tree is collapsed at the end anyway; 0: only then)")
      ->capture_default_str()
      ->check(inRange(0, 1e6));
  sub->add_option("--node-limit", o->nodeLimit, "most nodes the tree may grow to")->capture_default_str()->check(inRange(1, 2e9));  // within dvt::kMaxTreeNodes
  sub->add_option("--backend", o->backend, "gpu, cpu or auto (the GPU when there is one)")->capture_default_str()->check(backendChoice());
  sub->add_option("--render", o->render, "also draw the edited tree to this PNG")->check(outputFile());
  sub->add_option("--render-mode", o->renderMode, "raycast (rays through the tree, sub-voxel surface) or cubes (one per inside leaf)")
      ->capture_default_str();
  sub->add_option("--size", o->size, "the picture's width,height")
      ->delimiter(',')
      ->expected(2)
      ->capture_default_str()
      ->check(inRange(1, 8192));
  sub->add_option("-o,--output", o->output, "a mask (.nii.gz, the input's geometry), a mesh (.ply/.off/.obj/.vtk/.surf.gii) or a tree (.dvt)")->required()->check(outputFile());
  addMeshSpaceOption(*sub, o->space);
  bindAction(*sub, [o](nlohmann::json& r) {
    const bool toTree = endsWith(o->output, ".dvt"), toMesh = isMeshWritePath(o->output);
    require(toTree || toMesh || isVolumeWritePath(o->output), o->output + ": write a mask (.nii.gz, .nrrd, ...), a mesh (.ply, .off, .obj, .vtk, .surf.gii) or a tree (.dvt)");
    if (toMesh) requireMeshSpaceFor(o->output, meshSpace(o->space));
    require(o->renderMode == "raycast" || o->renderMode == "cubes", "--render-mode must be raycast or cubes, not " + o->renderMode);
    require(o->render.empty() || endsWith(o->render, ".png"), o->render + ": --render writes a PNG");
    const pipeline::EditRequest request{.depth = o->depth, .steps = *o->steps, .hierarchical = !o->flat, .nodeLimit = o->nodeLimit,
                               .collapseEvery = o->collapseEvery};
    const pipeline::EditInput input = pipeline::readEditInput(o->input, request);
    if (!toTree) {
      Volume header;
      header.dims = toMesh ? dvt::fieldGrid(meshSamplingDepth(input.frame, input.depth)) : input.frame.grid();
      header.type = toMesh ? ScalarType::Float32 : ScalarType::UInt8;
      checkOutputGrid(o->output, header);
    }
    pipeline::checkEditBudget(input, request);
    pipeline::Gpu gpu = pipeline::chooseBackend(o->backend);
    const pipeline::EditedTree edited = pipeline::applyEdits(input, request, gpu);
    const dvt::VolumeTree tree = edited.tree->tree();
    r.update(edited.figures(tree));
    r["renderer"] = gpu.renderer;
    r["edits"] = request.steps.size();
    if (toTree) {
      dvt::writeDvt(o->output, tree);
    } else if (toMesh) {
      const Volume field = dvt::sampleField(tree, meshSamplingDepth(tree.frame, edited.depth));
      extract::ExtractStats stats;
      const Mesh mesh = extract::extractSurface(field, {.iso = 0.0f, .backend = gpu.backend}, &stats);
      if (mesh.faceCount() == 0) throw Error(o->output + ": the edited volume is empty (no surface)", ErrorKind::Failure);
      writeMesh(o->output, mesh, {.space = meshSpace(o->space)});
      r["mesh"] = pipeline::surfaceFigures(mesh, &stats);
    } else {
      writeVolume(o->output, dvt::sampleMask(tree));
    }
    if (!o->render.empty()) {
      render::DvtView view{.camera = render::Camera::framing(render::insideBounds(tree), o->size[0], o->size[1], {0.6, 1, -0.5}),
                           .mode = o->renderMode == "cubes" ? render::DvtRenderMode::Cubes : render::DvtRenderMode::RayCast};
      writePng(o->render, pipeline::renderEditedTree(edited, tree, view, gpu));
      r["render"] = o->render;
    }
    logInfo("edit: " + std::to_string(request.steps.size()) + " edits, " + std::to_string(edited.tree->nodeCount()) + " nodes on the " +
            edited.backend + " -> " + o->output);
    return 0;
  }, exitCode);
}

}  // namespace isoatlas::app
