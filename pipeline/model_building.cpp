#include "pipeline/model_building.h"

#include <tbb/parallel_invoke.h>

#include <chrono>
#include <filesystem>

#include "atlas/atlas_previews.h"
#include "core/distance/mesh_distance.h"
#include "atlas/backfacing_quads.h"
#include "atlas/make_atlas.h"
#include "atlas/quantised_atlas.h"
#include "atlas/separate_codes.h"
#include "atlas/reconstruct.h"
#include "atlas/stamp_detail.h"
#include "atlas/tile_sides.h"
#include "core/error.h"
#include "core/image.h"
#include "core/progress.h"
#include "core/text.h"
#include "multires/folded_dense_triangles.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"
#include "render/mesh_render.h"

namespace isoatlas::pipeline {

Mesh prepareModelInput(Mesh mesh) {
  if (!mesh.allFacesHave(3)) {
    Mesh triangles = triangulated(mesh);
    logInfo("build: " + std::to_string(mesh.faceCount()) + " polygons split into " +
            std::to_string(triangles.faceCount()) + " triangles");
    mesh = std::move(triangles);
  }
  const Mesh used = dropUnusedVertices(mesh);
  if (used.vertexCount() < mesh.vertexCount())
    logInfo("build: dropped " + std::to_string(mesh.vertexCount() - used.vertexCount()) + " vertices that no face uses");
  return used;
}

void checkModelRequest(const ModelRequest& request) {
  require(!request.baseRatio || (*request.baseRatio > 0 && *request.baseRatio <= 1), "--base-ratio must be in (0, 1]");
  require(request.maxError >= 0, "--max-error must be positive");
  require(multires::isChartSize(request.chartSize),
          "--chart must be 2^k + 1 between 3 and " + std::to_string(multires::kMaxChartSize) + " (e.g. 33)");
  require(!request.relaxSweeps || (*request.relaxSweeps >= 0 && *request.relaxSweeps <= 1000), "--relax-sweeps must be between 0 and 1000");
}

namespace {

// The base mesh, its tiles and the atlas for one simplification.
struct Built {
  atlas::Model model;
  multires::SimplifyStats stats;
  multires::PairingStats pairing;
  atlas::ChartStats charts;
  int relaxSweeps = 0;
};

// The relaxation's sweeps: the request's, else none where the base is the dense mesh itself.
int relaxSweepsFor(const ModelRequest& request, const multires::SimplifyOptions& simplify, std::size_t denseVertices) {
  if (request.relaxSweeps) return *request.relaxSweeps;
  return multires::targetBaseVertices(simplify, denseVertices) == denseVertices ? 0 : atlas::kDefaultRelaxSweeps;
}

Built simplifyPairAndChart(const Mesh& dense, const ModelRequest& request, const multires::SimplifyOptions& simplify) {
  Built b;
  b.relaxSweeps = relaxSweepsFor(request, simplify, dense.vertexCount());
  b.model.chartSize = request.chartSize;
  multires::BaseMesh& base = b.model.base;
  base = multires::simplifyStellar(dense, simplify, &b.stats);
  logInfo("build: " + std::to_string(b.stats.denseVertices) + " -> " + std::to_string(b.stats.baseVertices) +
          " vertices in " + std::to_string(b.stats.seconds) + " s");
  b.pairing = multires::pairTriangles(base, dense);
  logInfo("build: " + std::to_string(b.pairing.tiles) + " tiles, " + std::to_string(b.pairing.splits) +
          " edge splits for the matching, " + std::to_string(b.pairing.seconds) + " s");
  b.model.atlas = atlas::makeAtlas(dense, base, request.chartSize, &b.charts, b.relaxSweeps);
  b.model.coincidentTexels = b.charts.coincidentTexels, b.model.gapTexels = b.charts.gapTexels;
  const atlas::AtlasLayout& layout = b.model.atlas.layout;
  logInfo("build: " + std::to_string(layout.charts) + " charts in a " + std::to_string(layout.width()) + " x " +
          std::to_string(layout.height()) + " atlas (" + std::to_string(layout.efficiency() * 100) + " % full), " +
          std::to_string(b.charts.coincidentTexels) + " coincident texels, " + std::to_string(b.charts.seconds) + " s");
  return b;
}

}  // namespace

atlas::Model buildModel(const Mesh& dense, const ModelRequest& request, nlohmann::json& r) {
  require(request.baseVertices <= dense.vertexCount(), "--base-vertices " + std::to_string(request.baseVertices) +
                                                         ": the mesh has only " + std::to_string(dense.vertexCount()) + " vertices");
  multires::SimplifyOptions simplify{.vertexRatio = request.baseRatio, .targetVertices = request.baseVertices};
  if (request.maxError > 0) simplify.maxError = request.maxError;
  Built built = simplifyPairAndChart(dense, request, simplify);
  // A small mesh kept whole by default (multires::defaultBaseVertices) stays so only where its tiles
  // sample cleanly: a sliver tile can put two texels at one place, in floats or in the codes (where
  // no free code lies within reach), and the capture then welds them into a non-manifold. Such a
  // mesh is simplified as a larger one is (a triangle of no area does it; no mesh of the corpus now).
  const bool whole = !request.baseRatio && request.baseVertices == 0 && built.stats.targetVertices == dense.vertexCount();
  if (whole) {
    atlas::SeparatedTexels codes;
    atlas::quantiseAtlas(built.model.atlas, built.model.base, &codes);
    if (built.charts.coincidentTexels > 0 || codes.joined > 0) {
      logInfo("build: the mesh kept whole puts texels at one place (" + std::to_string(built.charts.coincidentTexels) +
              " coincident, " + std::to_string(codes.joined) + " joined by their codes): simplified instead");
      simplify.targetVertices = multires::simplifiedBaseVertices(dense.vertexCount());
      built = simplifyPairAndChart(dense, request, simplify);
    }
  }
  atlas::Model& model = built.model;
  multires::BaseMesh& base = model.base;
  const multires::SimplifyStats& stats = built.stats;
  const multires::PairingStats& pairing = built.pairing;
  const atlas::ChartStats& charts = built.charts;
  r["base_whole"] = base.vertexCount() == dense.vertexCount();
  r["folded_dense_triangles"] = multires::countFoldedTriangles(dense, base);

  r["dense_vertices"] = dense.vertexCount();
  r["dense_triangles"] = dense.faceCount();
  r["base_vertices"] = base.vertexCount();
  r["base_triangles"] = base.triangleCount();
  r["base_triangles_before_matching"] = stats.baseTriangles;
  r["target_vertices"] = stats.targetVertices;
  r["reached_target"] = stats.reachedTarget;
  r["vertices_above_target"] = stats.baseVertices > stats.targetVertices ? stats.baseVertices - stats.targetVertices : 0;
  r["refused_welds"] = {{"point_outside", stats.refusals.pointOutside}, {"dense_triangle", stats.refusals.denseTriangle}};
  r["history_steps"] = stats.historySteps;
  r["history_bytes"] = stats.historyBytes;
  r["tiles"] = pairing.tiles;
  r["splits_for_matching"] = pairing.splits;
  r["vertices_in_too_few_tiles"] = pairing.shortVertices;
  r["mean_tile_orthogonality"] = pairing.meanOrthogonality;
  r["operators"] = {{"flips", stats.operators.flips}, {"face_welds", stats.operators.faceWelds},
                    {"edge_welds", stats.operators.edgeWelds}, {"boundary_welds", stats.operators.boundaryWelds}};
  r.update(atlasFigures(model));
  r["border_disagreements"] = charts.borderDisagreements;
  r["mean_history_steps"] = charts.meanHistorySteps;
  r["turned_texel_quads"] = charts.turnedTexelQuads;
  r["non_convex_chart_quads"] = charts.nonConvexChartQuads;
  r["snapped_texels"] = charts.snappedTexels;
  r["unturned_texels"] = charts.unturnedTexels;
  r["level_two_centres_moved"] = charts.levelTwoCentresMoved;
  r["kept_diagonals"] = charts.keptDiagonals;
  r["relax_sweeps"] = built.relaxSweeps;
  r["seconds_simplify"] = stats.seconds;
  r["seconds_match"] = pairing.seconds;
  r["seconds_chart"] = charts.seconds;
  const double diagonal = boundingBox(dense.positions).diagonal();
  r["bounding_box_diagonal"] = diagonal;
  r["dense_halfedge_bytes"] = atlas::halfedgeMeshBytes(dense);
  r["dense_ply_bytes"] = atlas::binaryPlyBytes(dense);
  if (request.hausdorff) {
    const auto start = std::chrono::steady_clock::now();
    const Hausdorff h = hausdorffDistance(dense, base.triangleMesh(), request.hausdorffFacePoints);
    r["hausdorff_base"] = h.symmetric();
    r["hausdorff_dense_to_base"] = h.aToB;
    r["hausdorff_base_to_dense"] = h.bToA;
    const double psnr = psnrDb(diagonal, h.symmetric());
    r["psnr_base_db"] = psnr;
    r["seconds_hausdorff"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    logInfo("build: base mesh Hausdorff " + std::to_string(h.symmetric()) + " (PSNR " + std::to_string(psnr) + " dB, CGAL)");
  }
  if (request.keepDense) {
    model.dense = dense;
  } else {
    base.denseTriangle.clear();
    base.denseBary.clear();
  }
  return std::move(model);
}

nlohmann::json atlasFigures(const atlas::Model& model) {
  const atlas::AtlasLayout& l = model.atlas.layout;
  nlohmann::json r{{"chart_size", model.chartSize},      {"charts", l.charts},
                   {"atlas_width", l.width()},           {"atlas_height", l.height()},
                   {"atlas_efficiency", l.efficiency()}, {"coincident_texels", model.coincidentTexels},
                   {"gap_texels", model.gapTexels},      {"quantisation_error", model.quantisationError}};
  auto where = [&](const std::string& name, const atlas::BackFacingQuads& q) {
    r[name + "_texel_quads"] = q.quads, r[name + "_texel_quad_charts"] = q.charts;
    r[name + "_worst_chart"] = q.worstChart, r[name + "_worst_chart_quads"] = q.worstChartQuads;
    r[name + "_worst_chart_at"] = {q.worstChartCentre.x, q.worstChartCentre.y, q.worstChartCentre.z};
  };
  where("backfacing", atlas::countBackFacingQuads(model.atlas));
  if (!model.atlas.triangleFaceNormals.empty()) where("folded", atlas::countFoldedQuads(model.atlas));
  return r;
}

void writeModelFiles(const atlas::Model& model, const std::string& path, const AtlasPreviewPaths& previews, nlohmann::json& r) {
  double quantisationError = 0;
  tbb::parallel_invoke([&] { quantisationError = atlas::writeModel(path, model); },
                       [&] {
                         if (!previews.positions.empty()) writePng(previews.positions, atlas::positionPreview(model.atlas));
                       },
                       [&] {
                         if (!previews.normals.empty()) writePng(previews.normals, atlas::normalPreview(model.atlas));
                       },
                       [&] {
                         if (!previews.backFacing.empty()) writePng(previews.backFacing, atlas::backFacingPreview(model.atlas));
                       });
  r["quantisation_error"] = quantisationError;
  r["model_bytes"] = std::filesystem::file_size(path);
  if (r.contains("dense_halfedge_bytes")) r["model_to_dense_halfedge"] = double(r["model_bytes"]) / double(r["dense_halfedge_bytes"]);
  if (r.contains("dense_ply_bytes")) r["model_to_dense_ply"] = double(r["model_bytes"]) / double(r["dense_ply_bytes"]);
}

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

namespace {

// The tiles whose faces at the finest level may start within `reach` of `centre`: those with a detail
// chart, those beside one (their fans start at its samples), and those with a texel that near (a
// tile without detail is its chart's texels there).
std::vector<std::uint32_t> tilesNear(const atlas::Model& model, const Vec3& centre, double reach) {
  const atlas::Atlas& a = model.atlas;
  const std::uint32_t n = a.layout.chartSize;
  std::vector<bool> near(a.layout.charts, false);
  const auto across = atlas::sidesAcross(model.base);
  for (const atlas::DetailChart& d : a.details) {
    near[d.tile] = true;
    for (const atlas::SideAcross& side : across[d.tile])
      if (side.tile != atlas::kNoTile) near[side.tile] = true;
  }
  for (std::uint32_t c = 0; c < a.layout.charts; ++c)
    for (std::uint32_t j = 0; j < n && !near[c]; ++j)
      for (std::uint32_t i = 0; i < n && !near[c]; ++i) near[c] = norm(a.position(c, i, j) - centre) < reach;
  std::vector<std::uint32_t> tiles;
  for (std::uint32_t c = 0; c < a.layout.charts; ++c)
    if (near[c]) tiles.push_back(c);
  return tiles;
}

}  // namespace

Image closeUp(const atlas::Model& model, const atlas::StampStats& stamp, double radius) {
  const double reach = 1.3 * radius;
  const Mesh finest = atlas::reconstructTiles(model.base, model.atlas, atlas::maxLevel(model.atlas), tilesNear(model, stamp.centre, reach));
  const Mesh near = selectFaces(finest, [&](std::size_t f) {
    const auto c = finest.face(f);
    return norm(finest.positions[c[0]] - stamp.centre) < reach;
  });
  const Vec3 worldUp = std::abs(stamp.normal.z) > 0.9 ? Vec3{0, 1, 0} : Vec3{0, 0, 1};
  // selectFaces keeps the normals of the vertices it keeps: the atlas's, stamped.
  return render::renderMesh(near, {.viewDirection = stamp.normal * -1, .up = worldUp});
}

atlas::StampStats stampModel(atlas::Model& model, const StampRequest& request, nlohmann::json& r) {
  require(!request.image.empty() || !request.text.empty(), "give --stamp IMAGE.png or --text WORD");
  require(request.image.empty() || request.text.empty(), "give --stamp or --text, not both");
  atlas::Stamp stamp;
  stamp.image = request.image.empty() ? renderText(request.text, 128, request.font) : readPng(request.image);
  stamp.at = request.at;
  stamp.radius = request.radius;
  stamp.depth = request.depth;
  stamp.detailSize = request.detailSize;
  const atlas::StampStats s = atlas::stampDetail(model.base, model.atlas, stamp);
  const double away = norm(s.centre - request.at);
  require(away <= request.radius, "--at lies " + std::to_string(away) + " mm from the surface, farther than --radius " +
                                      std::to_string(request.radius) + " (give a point at or near the surface)");
  require(s.texelsChanged + s.detailTexelsChanged > 0, "the stamp reaches no part of the surface (its image is blank there?)");
  r["centre"] = {s.centre.x, s.centre.y, s.centre.z};
  r["normal"] = {s.normal.x, s.normal.y, s.normal.z};
  r["detail_tiles"] = s.detailTiles;
  r["texels_changed"] = s.texelsChanged;
  r["detail_texels_changed"] = s.detailTexelsChanged;
  r["detail_charts"] = model.atlas.details.size();
  r["max_level"] = atlas::maxLevel(model.atlas);
  logInfo("edit-detail: stamped " + std::to_string(s.detailTiles) + " tiles' detail charts and " + std::to_string(s.texelsChanged) +
          " texels of their charts");
  return s;
}

void requireDenseOf(const atlas::Model& model, const Mesh& dense, const std::string& what) {
  const multires::BaseMesh& b = model.base;
  // Within float rounding: a mesh written as a float PLY (run's surface.ply) is still the same mesh.
  const double tolerance = 1e-6 * boundingBox(dense.positions).diagonal();
  for (std::size_t v = 0; v < b.vertexCount(); ++v) {
    const std::int64_t d = b.denseVertex[v];
    if (d < 0) continue;  // a vertex split in for the matching
    require(std::size_t(d) < dense.vertexCount() && norm(dense.positions[std::size_t(d)] - b.positions[v]) <= tolerance,
            what + ": not the mesh this model was built from (its base vertex " + std::to_string(v) + " is not that mesh's vertex " +
                std::to_string(d) + ")");
  }
}

}  // namespace isoatlas::pipeline
