#include "app/run_stages.h"

#include <algorithm>
#include <chrono>

#include "app/run_view_session.h"
#include "atlas/atlas_previews.h"
#include "atlas/reconstruct.h"
#include "core/image.h"
#include "core/mesh_io.h"
#include "core/volume_io.h"
#include "extract/extract_surface.h"
#include "edit/solids/volume_solid.h"
#include "pipeline/surface_figures.h"
#include "render/dvt_render.h"
#include "render/mesh_render.h"
#include "render/slice_render.h"

namespace isoatlas::app {

pipeline::Segmentation segmentStage(RunJob& job, const SegmentationSetup& setup, int iterations, bool halfResolutionStart) {
  std::optional<pipeline::Segmentation> result;
  job.stage("segment", [&] {
    result = pipeline::segmentVolume(job.volume, {.params = setup.params,
                                                  .seeds = setup.seeds,
                                                  .backend = job.gpu.backend,
                                                  .renderer = job.gpu.renderer,
                                                  .maxIterations = iterations,
                                                  .label = "run: segment",
                                                  .readPhi = true,
                                                  .halfResolutionStart = halfResolutionStart,
                                                  .topology = setup.topology});
    const pipeline::Segmentation& s = *result;
    const std::string maskFile = job.products.add("mask.nii.gz", "the segmentation: uint8, 1 inside, on the input's grid");
    writeVolume(maskFile, s.mask);
    writeVolume(job.products.add("phi.nii.gz", "the level set phi: float, > 0 inside, in voxels"), s.phi);
    job.report["segment"] = s.figures();
    job.report["segment"].update({{"target", setup.params.target}, {"width", setup.params.width}, {"alpha", setup.params.alpha}});
    writeViewSession(job.products.add("view-session.txt", "this segmentation and its edits replayed in the window: isoatlas view --script "
                                                          "view-session.txt (docs/view-script.md)"),
                     job.input, job.volume, setup.params, setup.seeds, s.stats.iterations,
                     s.halfResolution.iterations > 0 ? maskFile : std::string(), setup.edits.steps, s.topology, s.iterationsAfterFill);
    return std::to_string(s.insideVoxels) + " voxels in " + std::to_string(s.stats.iterations) + " iterations (" +
           (s.stats.converged ? "converged" : "not converged") + "): mask.nii.gz, phi.nii.gz";
  });
  return std::move(*result);
}

EditedVolume editStage(RunJob& job, const pipeline::Segmentation& s, const pipeline::EditRequest& edits,
                       const std::vector<std::unique_ptr<edit::dvt::DistanceSolid>>& solids) {
  EditedVolume out;
  if (edits.steps.empty()) {
    job.skipped("edit", "no --union or --subtract given");
    return out;
  }
  job.stage("edit", [&] {
    out.edited = pipeline::treeOfLevelSet(*s.levelSet, edits, job.gpu);
    pipeline::applySteps(*out.edited, edits, solids);
    out.tree = out.edited->tree->tree();
    writeVolume(job.products.add("mask_edited.nii.gz", "the segmentation after the edits: uint8, 1 inside"), edit::dvt::sampleMask(*out.tree));
    job.report["edit"] = out.edited->figures(*out.tree);
    std::string what;
    for (const pipeline::EditStep& e : edits.steps)
      what += std::string(what.empty() ? "" : ", ") + (e.op == edit::dvt::Op::Union ? "union " : "subtract ") + e.shape;
    job.report["edit"]["edits"] = what;
    return what + ": " + std::to_string(out.tree->nodeCount()) + " nodes on the " + out.edited->backend + ": mask_edited.nii.gz";
  });
  return out;
}

Mesh extractStage(RunJob& job, const pipeline::Segmentation& s, const EditedVolume& edit, std::size_t seeds, MeshSpace space) {
  Mesh surface;
  job.stage("extract", [&] {
    extract::ExtractStats stats;
    // Free, the largest component (noise leaves specks and cavities); preserved, one per seed (an edit
    // may have cut specks off them).
    const extract::ExtractOptions options{
        .iso = 0.0f, .largestComponents = s.topology == levelset::Topology::Free ? 1u : seeds, .backend = s.backend};
    surface = edit.tree ? extract::extractSurface(edit::dvt::sampleField(*edit.tree, edit.tree->frame.voxelDepth()), options, &stats)
                        : extract::extractLevelSet(*s.levelSet, options, &stats);
    const std::string frame = space == MeshSpace::Ras ? "RAS" : "LPS";
    writeMesh(job.products.add("surface.ply", "the extracted surface, closed and manifold, in world coordinates (mm, " + frame + ")"), surface,
              {.space = space});
    // The same surface for the neuroimaging viewers: GIfTI for freeview, Workbench, nilearn and niivue;
    // VTK tagged with its frame for 3D Slicer (which takes an untagged PLY as LPS).
    writeMesh(job.products.add("surface.surf.gii", "the surface as GIfTI, in RAS whatever --space says (freeview, Connectome Workbench, "
                                                   "nilearn, niivue)"),
              surface);
    writeMesh(job.products.add("surface.vtk", "the surface as VTK, tagged SPACE=" + frame + " (3D Slicer places it over the scan)"), surface,
              {.space = space});
    const nlohmann::json& figures = job.report["extract"] = pipeline::surfaceFigures(surface, &stats);
    return std::to_string(surface.faceCount()) + " triangles, genus " + std::to_string(figures["genus"].get<long long>()) + ", " +
           (figures["closed"].get<bool>() ? "closed" : "NOT closed") + ": surface.ply, .surf.gii, .vtk";
  });
  return surface;
}

std::string surfacePictures(RunJob& job, const EditedVolume& edit, const Mesh& surface, const pipeline::Segmentation& s,
                            const Vec3& firstSeed) {
  job.gpu.needGl();
  std::string names;
  if (edit.tree) {
    const render::DvtView view{.camera = render::Camera::framing(render::insideBounds(*edit.tree), 800, 600, {1, 0.3, -0.3})};
    writePng(job.products.add("edited_tree.png", "the edited segmentation, ray cast straight from the volume tree", true),
             pipeline::renderEditedTree(*edit.edited, *edit.tree, view, job.gpu));
    names = "edited_tree.png, ";
  }
  writePng(job.products.add("surface_left.png", "the extracted surface seen from the left", true),
           render::renderMesh(surface, {.viewDirection = {1, 0, 0}}));
  writePng(job.products.add("surface_top.png", "the extracted surface seen from above (anterior up)", true),
           render::renderMesh(surface, {.viewDirection = {0, 0, -1}, .up = {0, 1, 0}}));
  render::SliceOptions overlay;
  overlay.mask = &s.mask;
  writePng(job.products.add("segmentation_slices.png", "the segmentation over the input, through the first seed", true),
           render::renderSlices(job.volume, job.volume.indexToWorld(firstSeed), overlay));
  return names + "surface_left.png, surface_top.png, segmentation_slices.png";
}

BuiltModel buildModelFiles(const Mesh& surface, const pipeline::ModelRequest& request, const std::filesystem::path& dir) {
  const auto start = std::chrono::steady_clock::now();
  BuiltModel b{.products = {dir, {}}};
  const atlas::Model& model = b.model.emplace(pipeline::buildModel(surface, request, b.figures));
  const std::string path = b.products.add("model.isoatlas", "the multiresolution model: base mesh and atlas of charts (isoatlas eval, render)");
  const pipeline::AtlasPreviewPaths previews{
      b.products.add("position_atlas.png", "the atlas's positions as colours (x, y, z over the surface's box)", true),
      b.products.add("normal_atlas.png", "the atlas's normals as colours", true),
      b.products.add("backfacing_atlas.png", "where the atlas's texel quads turn: corners of folded quads red, of quads facing against the shading normals alone yellow", true)};
  pipeline::writeModelFiles(model, path, previews, b.figures);
  b.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return b;
}

MeasuredLevels measureLevels(const atlas::Model& model, const Mesh& surface, const std::vector<int>& levels, std::size_t facePoints,
                             const std::filesystem::path& dir) {
  const auto start = std::chrono::steady_clock::now();
  MeasuredLevels out{.products = {dir, {}}};
  out.levels = atlas::evaluateLevels(model.base, model.atlas, surface, levels, facePoints);
  writePng(out.products.add("psnr_per_level.png", "the model's accuracy per level: PSNR against the surface (CGAL: from the largest distance, and dashed from the RMS)", true),
           atlas::psnrPlot({{"model", out.levels}}));
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

void addProducts(RunJob& job, const pipeline::RunProducts& products) {
  job.products.all.insert(job.products.all.end(), products.all.begin(), products.all.end());
}

void modelStage(RunJob& job, BuiltModel& built, std::uint32_t chartSize) {
  const auto start = std::chrono::steady_clock::now();
  job.report["model"] = std::move(built.figures);
  addProducts(job, built.products);
  const atlas::Model& model = *built.model;
  const int shown = std::min(4, atlas::maxLevel(chartSize));
  job.gpu.needGl();
  writePng(job.products.add("model_level" + std::to_string(shown) + "_left.png",
                            "the model at level " + std::to_string(shown) + " seen from the left (atlas normals)", true),
           render::renderMesh(atlas::reconstructLevel(model.base, model.atlas, shown), {.viewDirection = {1, 0, 0}}));
  const double seconds = built.seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  job.stages.push_back({"build multiresolution model", "done",
                        std::to_string(model.base.vertexCount()) + " base vertices, " + std::to_string(model.atlas.layout.charts) +
                            " charts (" + std::to_string(int(model.atlas.layout.efficiency() * 100)) +
                            " % of the atlas): model.isoatlas (built beside the pictures)",
                        seconds});
}

void levelsStage(RunJob& job, const MeasuredLevels& measured) {
  nlohmann::json& m = job.report["model"];
  m["seconds_eval"] = measured.seconds;
  m["levels"] = pipeline::levelFiguresJson(measured.levels);
  addProducts(job, measured.products);
  const atlas::LevelFigures& top = measured.levels.back();
  job.stages.push_back({"measure the model's levels", "done",
                        "PSNR " + std::to_string(top.psnrDb) + " dB at level " + std::to_string(top.level) + ": psnr_per_level.png",
                        measured.seconds});
}

}  // namespace isoatlas::app
