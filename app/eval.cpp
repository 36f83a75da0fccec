// isoatlas eval: a model's accuracy per level against the dense mesh (CGAL's Hausdorff distance,
// PSNR), the atlas's figures, a PSNR plot and any level's mesh.
#include <filesystem>

#include "app/command.h"
#include "app/model_building.h"
#include "atlas/evaluate_levels.h"
#include "atlas/reconstruct.h"
#include "core/error.h"
#include "core/mesh_io.h"
#include "core/progress.h"

namespace isoatlas::app {
std::vector<int> parseLevels(const std::string& text, int maxLevel) {
  std::vector<int> levels;
  auto number = [&](const std::string& s) {
    std::size_t used = 0;
    int v = -1;
    try {
      v = std::stoi(s, &used);
    } catch (const std::exception&) {
    }
    require(used == s.size() && v >= 0 && v <= maxLevel,
            "--levels: '" + s + "' is not a level from 0 to " + std::to_string(maxLevel) + " (e.g. 0-" + std::to_string(maxLevel) + " or 0,4,8)");
    return v;
  };
  std::size_t at = 0;
  while (at <= text.size()) {
    const std::size_t comma = std::min(text.find(',', at), text.size());
    const std::string item = text.substr(at, comma - at);
    const std::size_t dash = item.find('-');
    if (dash == std::string::npos) {
      levels.push_back(number(item));
    } else {
      const int from = number(item.substr(0, dash)), to = number(item.substr(dash + 1));
      require(from <= to, "--levels: the range '" + item + "' runs backwards");
      for (int l = from; l <= to; ++l) levels.push_back(l);
    }
    at = comma + 1;
  }
  return levels;
}

nlohmann::json levelFiguresJson(const std::vector<atlas::LevelFigures>& levels) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& l : levels)
    out.push_back({{"level", l.level}, {"vertices", l.vertices}, {"triangles", l.triangles}, {"hausdorff", l.hausdorff},
                   {"psnr_db", l.psnrDb}, {"rms", l.rms}, {"psnr_rms_db", l.psnrRmsDb}, {"closed", l.closed},
                   {"manifold", l.manifold}});
  return out;
}

void addEvalCommand(CLI::App& app, int& exitCode) {
  auto* sub = app.add_subcommand("eval", "accuracy of a model per level against its dense mesh (PSNR, Hausdorff)");
  auto models = std::make_shared<std::vector<std::string>>();
  auto dense = std::make_shared<std::string>(), levelText = std::make_shared<std::string>(), plot = std::make_shared<std::string>();
  auto outMesh = std::make_shared<std::pair<int, std::string>>(-1, "");
  auto samples = std::make_shared<std::size_t>(atlas::kHausdorffFacePoints);
  sub->add_option("model", *models, "one or more .isoatlas models of the same dense mesh (the first is reported)")->required();
  sub->add_option("--dense", *dense, "the dense mesh the models were built from")->required();
  sub->add_option("--levels", *levelText, "levels to measure: 0-10, 4, or 0,4,10 (default: every level)");
  sub->add_option("--out-mesh-level", *outMesh, "write the first model's mesh at level L to FILE (.ply, .obj, .off, .stl)")
      ->type_name("L FILE");
  sub->add_option("--plot", *plot, "PSNR against level for every model, as a PNG");
  sub->add_option("--samples", *samples, "Hausdorff face samples per mesh")->capture_default_str();
  bindAction(*sub, [=](nlohmann::json& r) {
    require(plot->empty() || plot->ends_with(".png"), *plot + ": --plot writes a .png");
    require(*samples >= 1000, "--samples must be at least 1000");
    const Mesh denseMesh = prepareModelInput(readMesh(*dense));
    std::vector<std::pair<std::string, std::vector<atlas::LevelFigures>>> measured;
    for (std::size_t m = 0; m < models->size(); ++m) {
      const atlas::Model model = atlas::readModel((*models)[m]);
      const int top = atlas::maxLevel(model.atlas);
      const std::vector<int> levels = levelText->empty() ? parseLevels("0-" + std::to_string(top), top) : parseLevels(*levelText, top);
      if (m == 0) {
        if (outMesh->first != -1) {
          require(outMesh->first >= 0 && outMesh->first <= top, "--out-mesh-level: level " + std::to_string(outMesh->first) +
                                                                     " is outside 0.." + std::to_string(top));
          writeMesh(outMesh->second, atlas::reconstructLevel(model.base, model.atlas, outMesh->first));
        }
        r["model"] = (*models)[m];
        r.update(atlasFigures(model));
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
      if (m == 0) r["levels"] = levelFiguresJson(measured.back().second);
      else r["others"].push_back({{"model", (*models)[m]}, {"levels", levelFiguresJson(measured.back().second)}});
      for (const auto& l : measured.back().second)
        logInfo("eval: " + measured.back().first + " level " + std::to_string(l.level) + ": " + std::to_string(l.triangles) +
                " triangles, Hausdorff " + std::to_string(l.hausdorff) + ", PSNR " + std::to_string(l.psnrDb) + " dB (RMS: " +
                std::to_string(l.psnrRmsDb) + " dB)");
    }
    if (!plot->empty()) writePng(*plot, atlas::psnrPlot(measured));
    return 0;
  }, exitCode);
}

}  // namespace isoatlas::app
