// isoatlas build: the multiresolution model of a triangle mesh. Stellar simplification with local
// parametrisation, then the triquad base mesh by max-weight matching; the atlas issue adds the charts.
#include <chrono>

#include "app/command.h"
#include "atlas/model_file.h"
#include "core/error.h"
#include "core/mesh_io.h"
#include "core/progress.h"
#include "multires/mesh_distance.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"

namespace isoatlas::app {
namespace {

struct BuildOptions {
  std::string input, output, baseOnly;
  double baseRatio = 0.01;
  std::size_t baseVertices = 0;
  double maxError = 0;
  int chart = 33;
  bool noHausdorff = false;
};

// Polygons become triangle fans and vertices no face uses are dropped: the multiresolution stage
// takes any manifold polygon mesh a scanner or modeller writes.
Mesh prepareInput(Mesh mesh) {
  if (!mesh.allFacesHave(3)) {
    Mesh triangles;
    triangles.positions = mesh.positions;
    for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
      const auto c = mesh.face(f);
      for (std::size_t i = 1; i + 1 < c.size(); ++i) triangles.addFace({c[0], c[i], c[i + 1]});
    }
    logInfo("build: " + std::to_string(mesh.faceCount()) + " polygons split into " +
            std::to_string(triangles.faceCount()) + " triangles");
    mesh = std::move(triangles);
  }
  const Mesh used = dropUnusedVertices(mesh);
  if (used.vertexCount() < mesh.vertexCount())
    logInfo("build: dropped " + std::to_string(mesh.vertexCount() - used.vertexCount()) + " vertices that no face uses");
  return used;
}

}  // namespace

void addBuildCommand(CLI::App& app, int& exitCode) {
  auto* sub = app.add_subcommand("build", "multiresolution model of a triangle mesh: stellar simplification, triquad base mesh");
  auto o = std::make_shared<BuildOptions>();
  sub->add_option("mesh", o->input, "a 2-manifold mesh (.off, .ply, .obj, .stl), closed or with boundaries")->required();
  sub->add_option("-o,--output", o->output, "the model file (.isoatlas)");
  sub->add_option("--base-ratio", o->baseRatio, "base vertices as a fraction of the dense ones")->capture_default_str();
  sub->add_option("--base-vertices", o->baseVertices, "base vertex count (instead of --base-ratio)");
  sub->add_option("--max-error", o->maxError, "never weld where the quadric RMS distance exceeds this (mm)");
  sub->add_option("--chart", o->chart, "chart size in texels per side, 2^k + 1")->capture_default_str();
  sub->add_option("--base-only", o->baseOnly, "also write the triquad base mesh as an OBJ of quads");
  sub->add_flag("--no-hausdorff", o->noHausdorff, "skip measuring the base mesh's Hausdorff distance");
  bindAction(*sub, [o](nlohmann::json& r) {
    require(!o->output.empty() || !o->baseOnly.empty(), "build: give -o MODEL.isoatlas, --base-only BASE.obj, or both");
    require(o->output.empty() || o->output.ends_with(".isoatlas"), o->output + ": the model file must end in .isoatlas");
    require(o->baseOnly.empty() || o->baseOnly.ends_with(".obj"), o->baseOnly + ": --base-only writes an .obj");
    require(o->baseRatio > 0 && o->baseRatio <= 1, "--base-ratio must be in (0, 1]");
    require(o->maxError >= 0, "--max-error must be positive");
    require(multires::isChartSize(std::uint32_t(o->chart)),
            "--chart must be 2^k + 1 between 3 and " + std::to_string(multires::kMaxChartSize) + " (e.g. 33)");

    const Mesh dense = prepareInput(readMesh(o->input));
    multires::SimplifyOptions simplify{.vertexRatio = o->baseRatio, .targetVertices = o->baseVertices};
    if (o->maxError > 0) simplify.maxError = o->maxError;
    multires::SimplifyStats stats;
    multires::BaseMesh base = multires::simplifyStellar(dense, simplify, &stats);
    logInfo("build: " + std::to_string(stats.denseVertices) + " -> " + std::to_string(stats.baseVertices) +
            " vertices in " + std::to_string(stats.seconds) + " s");
    const multires::PairingStats pairing = multires::pairTriangles(base, dense);
    logInfo("build: " + std::to_string(pairing.tiles) + " tiles, " + std::to_string(pairing.splits) +
            " edge splits for the matching, " + std::to_string(pairing.seconds) + " s");

    r["dense_vertices"] = dense.vertexCount();
    r["dense_triangles"] = dense.faceCount();
    r["base_vertices"] = base.vertexCount();
    r["base_triangles"] = base.triangleCount();
    r["base_triangles_before_matching"] = stats.baseTriangles;
    r["target_vertices"] = stats.targetVertices;
    r["reached_target"] = stats.reachedTarget;
    r["tiles"] = pairing.tiles;
    r["splits_for_matching"] = pairing.splits;
    r["zero_weight_tiles"] = pairing.zeroWeightTiles;
    r["mean_tile_orthogonality"] = pairing.meanOrthogonality;
    r["operators"] = {{"flips", stats.operators.flips}, {"face_welds", stats.operators.faceWelds},
                      {"edge_welds", stats.operators.edgeWelds}, {"boundary_welds", stats.operators.boundaryWelds}};
    r["folded_before_untangle"] = stats.untangle.foldedBefore;
    r["folded_after_untangle"] = stats.untangle.foldedAfter;
    r["untangled_vertices"] = stats.untangle.movedVertices;
    r["seconds_untangle"] = stats.untangle.seconds;
    r["seconds_simplify"] = stats.seconds;
    r["seconds_match"] = pairing.seconds;
    const double diagonal = boundingBox(dense.positions).diagonal();
    r["bounding_box_diagonal"] = diagonal;
    if (!o->noHausdorff) {
      const auto start = std::chrono::steady_clock::now();
      const multires::Hausdorff h = multires::hausdorffDistance(dense, base.triangleMesh());
      r["hausdorff_base"] = h.symmetric();
      r["hausdorff_base_mean"] = std::max(h.meanAToB, h.meanBToA);
      r["hausdorff_dense_to_base"] = h.aToB;
      r["hausdorff_base_to_dense"] = h.bToA;
      const double psnr = multires::psnrDb(diagonal, h.symmetric());
      r["psnr_base_db"] = psnr;
      r["seconds_hausdorff"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      logInfo("build: base mesh Hausdorff " + std::to_string(h.symmetric()) + " (PSNR " +
              std::to_string(psnr) + " dB)");
    }
    if (!o->baseOnly.empty()) writeMesh(o->baseOnly, base.quadMesh(), {.binary = false, .normals = false});
    if (!o->output.empty()) atlas::writeModel(o->output, {.chartSize = std::uint32_t(o->chart), .dense = dense, .base = base});
    return 0;
  }, exitCode);
}

}  // namespace isoatlas::app
