// The multiresolution model `build` and `run` share: stellar simplification with local
// parametrisation, the triquad base mesh by max-weight matching, one chart per tile packed into the
// atlas, and the base mesh's Hausdorff distance to the dense mesh (CGAL's).
#pragma once
#include <nlohmann/json.hpp>

#include <optional>
#include <string>

#include "atlas/evaluate_levels.h"
#include "core/distance/mesh_distance.h"
#include "atlas/make_atlas.h"
#include "atlas/model_file.h"
#include "atlas/stamp_detail.h"
#include "core/image.h"
#include "core/mesh.h"
#include "core/text.h"

namespace isoatlas::pipeline {

struct ModelRequest {
  std::optional<double> baseRatio;  // unset: multires::defaultBaseVertices
  std::size_t baseVertices = 0;     // instead of baseRatio when set
  double maxError = 0;              // 0: unbounded
  std::uint32_t chartSize = 33;
  // Texels follow the surface's bending (0: uniform in each tile). Unset: atlas::kDefaultRelaxSweeps,
  // or 0 where the mesh is its own base (each tile two of its triangles, which a uniform grid
  // samples exactly; relaxed, it folds: bench/RESULTS.md, "Whole meshes unrelaxed").
  std::optional<int> relaxSweeps;
  bool keepDense = false;  // the model keeps the dense mesh and its parametrisation
  bool hausdorff = true;   // measure the base mesh against the dense one
  std::size_t hausdorffFacePoints = kHausdorffFacePoints;
};

// Throws Error naming the option (--base-ratio, --max-error, --chart, --relax-sweeps) when the request is out of range.
void checkModelRequest(const ModelRequest& request);
// `dense`: a triangle mesh (prepareModelInput's). Fills `figures` with what each stage measured.
atlas::Model buildModel(const Mesh& dense, const ModelRequest& request, nlohmann::json& figures);

// Polygons are split into triangles (core/mesh.h, triangulated) and vertices no face uses are
// dropped: the multiresolution stage takes any manifold polygon mesh a scanner or modeller writes.
Mesh prepareModelInput(Mesh mesh);

// chart_size, charts, atlas_width, atlas_height, atlas_efficiency, coincident_texels, gap_texels,
// quantisation_error, and backfacing_texel_quads (atlas/backfacing_quads.h) with the charts that hold
// them and the worst one: the atlas's figures, as build and eval report them; where the atlas was
// made here (it has its dense faces' normals), folded_texel_quads and theirs too.
nlohmann::json atlasFigures(const atlas::Model& model);

// Where the atlas's pictures go (atlas::positionPreview, atlas::normalPreview): an empty path writes none.
struct AtlasPreviewPaths {
  std::string positions, normals, backFacing;
};
// Writes the model and the atlas's pictures side by side; adds quantisation_error, model_bytes and
// the model's ratios to the dense mesh to `figures`.
void writeModelFiles(const atlas::Model& model, const std::string& path, const AtlasPreviewPaths& previews, nlohmann::json& figures);

// Throws Error (bad input, naming `what`) unless `dense` is the mesh `model` was built from: each base
// vertex that is a dense vertex sits where that vertex does (welds never move a vertex), to within
// float rounding.
void requireDenseOf(const atlas::Model& model, const Mesh& dense, const std::string& what);

// Levels as eval and run take them: "0-10", "4" or "0,2,10", each within 0 .. maxLevel; throws
// Error naming --levels otherwise.
std::vector<int> parseLevels(const std::string& text, int maxLevel);

// The report's `levels` list: level, vertices, triangles, hausdorff, psnr_db, closed, manifold.
nlohmann::json levelFiguresJson(const std::vector<atlas::LevelFigures>& levels);

// A stamp as edit-detail and run give it: a PNG or a word (rendered with `font`), where, how wide
// and deep, and the detail charts' size.
struct StampRequest {
  std::string image, text, font = kDefaultFont;
  Vec3 at;
  double radius = 0, depth = 0;
  std::uint32_t detailSize = 129;
};
// Stamps the model; adds centre, normal, detail_tiles, texels_changed, detail_texels_changed,
// detail_charts and max_level to `figures`. Throws Error(BadInput) when the stamp reaches nothing or
// `at` lies farther than `radius` from the surface; the model may then be stamped already, so a caller
// that goes on without the stamp stamps a copy (run does; edit-detail writes nothing on an error).
atlas::StampStats stampModel(atlas::Model& model, const StampRequest& request, nlohmann::json& figures);
// The stamped region at the model's finest level, seen along the stamp's normal.
Image closeUp(const atlas::Model& model, const atlas::StampStats& stamp, double radius);

}  // namespace isoatlas::pipeline
