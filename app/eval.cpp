// isoatlas eval: a model's accuracy per level against the dense mesh (CGAL's Hausdorff distance,
// PSNR), the atlas's figures, a PSNR plot and any level's mesh.
#include <filesystem>
#include <optional>

#include "app/command.h"
#include "app/options.h"
#include "pipeline/model_building.h"
#include "atlas/evaluate_levels.h"
#include "atlas/reconstruct.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/mesh_io.h"
#include "core/progress.h"

namespace isoatlas::app {
void addEvalCommand(CLI::App& app, int& exitCode) {
  auto* sub = app.add_subcommand("eval", "accuracy of a model per level against its dense mesh (PSNR, Hausdorff)");
  auto models = std::make_shared<std::vector<std::string>>();
  auto dense = std::make_shared<std::string>(), levelText = std::make_shared<std::string>(), plot = std::make_shared<std::string>();
  auto outMesh = std::make_shared<std::pair<int, std::string>>(-1, "");
  auto samples = std::make_shared<std::size_t>(kHausdorffFacePoints);
  sub->add_option("model", *models, "one or more .isoatlas models of the same dense mesh (the first is reported)")->required();
  sub->add_option("--dense", *dense, "the dense mesh the models were built from")->required();
  sub->add_option("--levels", *levelText, "levels to measure: 0-10, 4, or 0,4,10 (default: every level)");
  sub->add_option("--out-mesh-level", *outMesh, "write the first model's mesh at level L to FILE (.ply, .obj, .off, .vtk or .surf.gii)")
      ->type_name("L FILE")
      ->check(inRange(0, kMaxLevel).application_index(0));
  sub->add_option("--plot", *plot, "PSNR against level for every model, as a PNG")->check(outputFile());
  auto space = std::make_shared<std::string>("ras");
  addMeshSpaceOption(*sub, *space);
  sub->add_option("--samples", *samples, "Hausdorff face samples per mesh")->capture_default_str()->check(inRange(kMinSamples, kMaxSamples));
  bindAction(*sub, [=](nlohmann::json& r) {
    require(plot->empty() || plot->ends_with(".png"), *plot + ": --plot writes a .png");
    if (outMesh->first != -1) {
      require(isMeshWritePath(outMesh->second), outMesh->second + ": --out-mesh-level writes a mesh (.ply, .obj, .off, .vtk or .surf.gii)");
      requireOutputFolder(outMesh->second);
      requireMeshSpaceFor(outMesh->second, meshSpace(*space));
    }
    std::optional<Mesh> levelMesh;  // written once every model has been read and checked
    const Mesh denseMesh = pipeline::prepareModelInput(readMesh(*dense));
    std::vector<std::pair<std::string, std::vector<atlas::LevelFigures>>> measured;
    for (std::size_t m = 0; m < models->size(); ++m) {
      const atlas::Model model = atlas::readModel((*models)[m]);
      pipeline::requireDenseOf(model, denseMesh, "--dense " + *dense);
      const int top = atlas::maxLevel(model.atlas);
      const std::vector<int> levels = levelText->empty() ? pipeline::parseLevels("0-" + std::to_string(top), top) : pipeline::parseLevels(*levelText, top);
      if (m == 0) {
        if (outMesh->first != -1) {
          require(outMesh->first >= 0 && outMesh->first <= top, "--out-mesh-level: level " + std::to_string(outMesh->first) +
                                                                     " is outside 0.." + std::to_string(top));
          levelMesh = atlas::reconstructLevel(model.base, model.atlas, outMesh->first);
        }
        r["model"] = (*models)[m];
        r.update(pipeline::atlasFigures(model));
        r["model_bytes"] = std::filesystem::file_size((*models)[m]);
        r["dense_halfedge_bytes"] = atlas::halfedgeMeshBytes(denseMesh);
        r["dense_ply_bytes"] = atlas::binaryPlyBytes(denseMesh);
        r["model_to_dense_halfedge"] = double(r["model_bytes"]) / double(r["dense_halfedge_bytes"]);
        r["model_to_dense_ply"] = double(r["model_bytes"]) / double(r["dense_ply_bytes"]);
        r["dense_triangles"] = denseMesh.faceCount();
        r["bounding_box_diagonal"] = boundingBox(denseMesh.positions).diagonal();
        r["hausdorff_face_samples"] = *samples;
      }
      measured.emplace_back(std::filesystem::path((*models)[m]).stem().string(),
                            atlas::evaluateLevels(model.base, model.atlas, denseMesh, levels, *samples));
      if (m == 0) r["levels"] = pipeline::levelFiguresJson(measured.back().second);
      else r["others"].push_back({{"model", (*models)[m]}, {"levels", pipeline::levelFiguresJson(measured.back().second)}});
      for (const auto& l : measured.back().second)
        logInfo("eval: " + measured.back().first + " level " + std::to_string(l.level) + ": " + std::to_string(l.triangles) +
                " triangles, Hausdorff " + std::to_string(l.hausdorff) + ", PSNR " + std::to_string(l.psnrDb) + " dB (RMS: " +
                std::to_string(l.psnrRmsDb) + " dB)");
    }
    if (levelMesh) writeMesh(outMesh->second, *levelMesh, {.space = meshSpace(*space)});
    if (!plot->empty()) writePng(*plot, atlas::psnrPlot(measured));
    return 0;
  }, exitCode);
}

}  // namespace isoatlas::app
