// bench/atlas: the whole model of a dense mesh, stage by stage (simplify, match, chart + pack:
// seconds and peak resident memory on stderr), beside CGAL's edge collapse to the same base size
// for the time; the model's bytes beside the dense mesh as a plain halfedge mesh and as a binary
// PLY; the atlas's efficiency beside the paper's best; the parametrisation's folds (dense
// triangles drawn straight, coincident and gap texels, texel quads folded, facing against the
// shading normals and turned as sampled, texels drawn onto dense vertices (snap_texels.h), border
// samples the two charts of an edge disagree on); eval's seconds; PSNR at the even
// levels (CGAL: from the largest distance and from the RMS distance) beside the faithful-model
// issue's target at level 10 for that mesh (beside the base mesh's where it names none). Cases: bunny00, elephant, fandisk, mannequin-devil
// (one boundary loop), camel, lion-head and the demo's white-matter surface (ch2). Writes the PSNR
// per level of every case to bench/atlas_psnr.png.
#include <chrono>
#include <filesystem>

#include "atlas/backfacing_quads.h"
#include "atlas/evaluate_levels.h"
#include "atlas/make_atlas.h"
#include "atlas/model_file.h"
#include "bench/bench_util.h"
#include "bench/cgal_simplify.h"
#include "bench/derived_data.h"
#include "core/mesh_io.h"
#include "multires/folded_dense_triangles.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"

using namespace isoatlas;

namespace {

double since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The faithful-model issue's targets at level 10, by the largest distance (dB); 0 where it names none.
double targetDb(const std::string& name) {
  if (name == "bunny00") return 70;
  if (name == "ch2 white matter") return 60;
  if (name == "mannequin-devil") return 55;
  if (name == "fandisk" || name == "elephant") return 50;
  return 0;
}

std::vector<atlas::LevelFigures> measure(const std::string& name, const Mesh& dense) {
  const std::string caseName = name + " (" + std::to_string(dense.faceCount()) + " triangles)";
  auto start = std::chrono::steady_clock::now();
  multires::BaseMesh base = multires::simplifyStellar(dense, {});
  const double simplify = since(start);
  const double simplifyRss = bench::peakRssMiB();
  start = std::chrono::steady_clock::now();
  multires::pairTriangles(base, dense);
  const double match = since(start);
  const double matchRss = bench::peakRssMiB();
  start = std::chrono::steady_clock::now();
  atlas::ChartStats charts;
  atlas::Model model{.chartSize = 33, .base = base, .atlas = atlas::makeAtlas(dense, base, 33, &charts), .dense = {}};
  const double chart = since(start);
  const double chartRss = bench::peakRssMiB();
  const std::size_t foldedDense = multires::countFoldedTriangles(dense, model.base);
  model.base.denseTriangle.clear(), model.base.denseBary.clear();
  const std::string path = (std::filesystem::temp_directory_path() / "bench_atlas.isoatlas").string();
  atlas::writeModel(path, model);
  const double modelBytes = double(std::filesystem::file_size(path));
  const atlas::BackFacingQuads backFacing = atlas::countBackFacingQuads(model.atlas), folded = atlas::countFoldedQuads(model.atlas);
  std::filesystem::remove(path);
  std::fprintf(stderr,
               "bench atlas: %s: simplify %.2f s (peak RSS %.0f MiB), match %.3f s (%.0f MiB), chart + pack %.2f s (%.0f MiB); "
               "%u charts, %llu coincident and %llu gap texels of %llu, %llu texel quads turned as sampled, %llu drawn backwards, %zu dense triangles folded drawn straight\n",
               caseName.c_str(), simplify, simplifyRss, match, matchRss, chart, chartRss, model.atlas.layout.charts,
               (unsigned long long)charts.coincidentTexels, (unsigned long long)charts.gapTexels, (unsigned long long)charts.texels,
               (unsigned long long)charts.turnedTexelQuads, (unsigned long long)backFacing.quads, foldedDense);
  for (const auto& [stage, seconds] : {std::pair{"simplify", simplify}, {"match", match}, {"chart + pack", chart}})
    bench::report("atlas", caseName, std::string("seconds ") + stage, seconds, "seconds, whole model", simplify + match + chart, false);
  bench::report("atlas", caseName, "coincident texels", double(charts.coincidentTexels), "texels", double(charts.texels), false);
  bench::report("atlas", caseName, "gap texels", double(charts.gapTexels), "texels", double(charts.texels), false);
  bench::report("atlas", caseName, "texel quads turned as sampled (first corner)", double(charts.turnedTexelQuads), "texels", double(charts.texels), false);
  bench::report("atlas", caseName, "texel quads folded (folded_texel_quads)", double(folded.quads), "texel quads", double(folded.total), false);
  bench::report("atlas", caseName, "texel quads facing against the shading normals (backfacing_texel_quads)", double(backFacing.quads),
                "texel quads", double(backFacing.total), false);
  bench::report("atlas", caseName, "texels drawn onto dense vertices the grid missed", double(charts.snappedTexels), "texels",
                double(charts.texels), false);
  bench::report("atlas", caseName, "charts whose centre moved for level 2", double(charts.levelTwoCentresMoved), "charts",
                double(model.atlas.layout.charts), false);
  bench::report("atlas", caseName, "border samples the two charts disagree on", double(charts.borderDisagreements), "texels",
                double(charts.texels), false);
  bench::report("atlas", caseName, "dense triangles folded drawn straight", double(foldedDense), "dense triangles",
                double(dense.faceCount()), false);

  double cgalSeconds = 0;
  bench::cgalSimplify(dense, base.triangleCount() * 3 / 2, cgalSeconds);
  bench::report("atlas", caseName, "seconds, whole model (simplify, match, chart, pack)", simplify + match + chart,
                "CGAL edge collapse (GH plane) to the base size alone", cgalSeconds);
  bench::report("atlas", caseName, "model bytes (base mesh + atlas)", modelBytes, "the dense mesh as a plain halfedge mesh",
                double(atlas::halfedgeMeshBytes(dense)));
  bench::report("atlas", caseName, "model bytes (base mesh + atlas)", modelBytes, "the dense mesh as a binary PLY",
                double(atlas::binaryPlyBytes(dense)));
  bench::report("atlas", caseName, "atlas efficiency", model.atlas.layout.efficiency(), "the paper's best (Kikito)", 0.939, false);
  start = std::chrono::steady_clock::now();
  const std::vector<atlas::LevelFigures> levels = atlas::evaluateLevels(model.base, model.atlas, dense, {0, 2, 4, 6, 8, 10});
  bench::report("atlas", caseName, "seconds eval (levels 0, 2, ..., 10)", since(start), "seconds, whole model",
                simplify + match + chart, false);
  const double target = targetDb(name);
  for (const atlas::LevelFigures& l : levels) {
    if (target > 0)
      bench::report("atlas", caseName, "PSNR at level " + std::to_string(l.level) + " (dB)", l.psnrDb, "the issue's target at level 10",
                    target, false);
    else
      bench::report("atlas", caseName, "PSNR at level " + std::to_string(l.level) + " (dB)", l.psnrDb,
                    "PSNR at level 0 (the base mesh)", levels.front().psnrDb, false);
    bench::report("atlas", caseName, "PSNR by RMS at level " + std::to_string(l.level) + " (dB)", l.psnrRmsDb,
                  "PSNR by the largest distance", l.psnrDb, false);
  }
  return levels;
}

}  // namespace

// bench_atlas [DATA [NAME ...]]: NAME is a mesh in DATA/meshes (without .off) or "white-matter";
// without names, the seven.
int main(int argc, char** argv) {
  const std::string data = argc > 1 ? argv[1] : "data";
  std::vector<std::string> names(argv + std::min(argc, 2), argv + argc);
  if (names.empty()) names = {"bunny00", "elephant", "fandisk", "mannequin-devil", "camel", "lion-head", "white-matter"};
  std::vector<std::pair<std::string, std::vector<atlas::LevelFigures>>> plotted;
  for (const std::string& name : names) {
    const Mesh dense = name == "white-matter" ? bench::ch2WhiteMatterSurface(data) : readMesh(data + "/meshes/" + name + ".off");
    plotted.emplace_back(name == "white-matter" ? "ch2 white matter" : name, measure(name == "white-matter" ? "ch2 white matter" : name, dense));
  }
  const std::filesystem::path plot = std::filesystem::path(ISOATLAS_BENCH_DIR) / "atlas_psnr.png";
  writePng(plot.string(), atlas::psnrPlot(plotted));
  std::fprintf(stderr, "bench atlas: wrote %s\n", plot.c_str());
  return 0;
}
