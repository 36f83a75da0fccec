// The multiresolution model `build` and `run` share: stellar simplification with local
// parametrisation, the triquad base mesh by max-weight matching, one chart per tile packed into the
// atlas, and the base mesh's Hausdorff distance to the dense mesh (CGAL's).
#pragma once
#include <nlohmann/json.hpp>

#include <string>

#include "atlas/evaluate_levels.h"
#include "atlas/model_file.h"
#include "core/image.h"
#include "core/mesh.h"

namespace isoatlas::app {

struct ModelRequest {
  double baseRatio = 0.01;
  std::size_t baseVertices = 0;  // instead of baseRatio when set
  double maxError = 0;           // 0: unbounded
  std::uint32_t chartSize = 33;
  bool keepDense = false;  // the model keeps the dense mesh and its parametrisation
  bool hausdorff = true;   // measure the base mesh against the dense one
};

// `dense`: a triangle mesh (prepareModelInput's). Fills `figures` with what each stage measured.
atlas::Model buildModel(const Mesh& dense, const ModelRequest& request, nlohmann::json& figures);

// Polygons become triangle fans and vertices no face uses are dropped: the multiresolution stage
// takes any manifold polygon mesh a scanner or modeller writes.
Mesh prepareModelInput(Mesh mesh);

// Writes the model and the atlas previews (position_atlas.png, normal_atlas.png into
// `previewDir` unless empty); adds model_bytes and dense_halfedge_bytes to `figures`.
void writeModelFiles(const atlas::Model& model, const std::string& path, const std::string& previewDir, nlohmann::json& figures);

// Levels as eval and run take them: "0-10", "4" or "0,2,10", each within 0 .. maxLevel; throws
// Error naming --levels otherwise.
std::vector<int> parseLevels(const std::string& text, int maxLevel);

// The report's `levels` list: level, vertices, triangles, hausdorff, psnr_db, closed, manifold.
nlohmann::json levelFiguresJson(const std::vector<atlas::LevelFigures>& levels);

}  // namespace isoatlas::app
