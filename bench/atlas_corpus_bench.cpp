// bench/atlas_corpus: the model over the whole mesh corpus, not the seven cases bench/atlas tunes
// on. Cases: every mesh of data/meshes that reads and, its polygons split as `isoatlas build` splits
// them, is a closed, oriented 2-manifold of at most
// ISOATLAS_BENCH_CORPUS_MOST_TRIANGLES triangles (500,000 unless set), and the demo's white-matter
// surface (left out with ISOATLAS_BENCH_CORPUS_WHITE_MATTER=0). Each is built as `isoatlas build`
// builds it (pipeline::buildModel) and read back from its model file (the quantised atlas a user gets). Per case:
//   - PSNR at levels 0, 2, ..., 10 by the largest distance and by the RMS distance (CGAL), and at each
//     level below the dense mesh's size the gap to meshoptimizer's simplifier at the same triangle
//     count (bench/meshopt_simplify.h), measured by the same ruler; whether every level is at least
//     the one below;
//   - texel quads folded (against the dense faces' normals) and facing against the shading normals
//     (backfacing_quads.h);
//   - level 10 captured from the GPU at three splits (--cpu-level 0 --gpu-level 5, 4 and 3, 8 and 1),
//     welded by position: closed, oriented 2-manifolds or not;
//   - the model's bytes over the dense mesh's binary PLY, beside Draco's (14-bit positions);
//   - seconds to build and to evaluate.
// Then the distribution over the cases (minimum, median, worst case named) of each figure beside the
// issue's targets, as JSON lines (over every case, and over the cases of at least 5,000 triangles:
// scans and surfaces rather than polyhedra of a few faces); a table of every case on stderr (for
// bench/RESULTS.md); and bench/atlas_corpus.png: level-10 PSNR by both measures, cases sorted.
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>

#include "atlas/backfacing_quads.h"
#include "atlas/evaluate_levels.h"
#include "atlas/make_atlas.h"
#include "atlas/model_file.h"
#include "bench/bench_util.h"
#include "bench/derived_data.h"
#include "bench/meshopt_simplify.h"
#include "core/gl/context.h"
#include "core/image.h"
#include "core/mesh_io.h"
#include "core/mesh_topology.h"
#include "core/plot.h"
#include "pipeline/model_building.h"
#include "render/atlas_render.h"
#include "render/model_lod.h"

using namespace isoatlas;

namespace {

constexpr int kLevels[] = {0, 2, 4, 6, 8, 10};
constexpr int kSplits[3][2] = {{0, 5}, {4, 3}, {8, 1}};  // (CPU levels, GPU halvings) making level 10
constexpr double kWorstTargetDb = 55, kMedianTargetDb = 65;
// PSNR beyond float positions' precision (an exact copy of a polyhedron: meshoptimizer keeps a cube's
// 12 triangles exactly) counts as this much in the gaps, so that rounding does not set them.
constexpr double kExactDb = 150;

double since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::size_t envCount(const char* name, std::size_t fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::size_t(std::strtoull(v, nullptr, 10)) : fallback;
}

struct Case {
  std::string name;
  Mesh dense;
};

// Whether a file's stem is one of `only`'s comma-separated names (all when `only` is empty).
bool chosen(const std::string& only, const std::string& stem) {
  return only.empty() || ("," + only + ",").find("," + stem + ",") != std::string::npos;
}

// The corpus: data/meshes' closed oriented 2-manifolds up to `most` triangles, by name; of them only
// those `only` names (comma-separated stems), when it names any.
std::vector<Case> corpus(const std::string& data, std::size_t most, bool whiteMatter, const std::string& only) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(data + "/meshes"))
    if ((entry.path().extension() == ".off" || entry.path().extension() == ".ply") && chosen(only, entry.path().stem().string()))
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  std::vector<Case> cases;
  for (const auto& file : files) {
    Mesh mesh;
    try {
      mesh = pipeline::prepareModelInput(readMesh(file.string()));  // polygons split, as `isoatlas build` does
    } catch (const std::exception&) {
      continue;  // not a mesh this reader takes
    }
    const MeshTopology t = analyzeTopology(mesh);
    if (!t.closed || !t.manifold || !t.oriented || mesh.faceCount() > most) continue;
    cases.push_back({file.filename().string(), std::move(mesh)});
  }
  if (whiteMatter) cases.push_back({"ch2 white matter", bench::ch2WhiteMatterSurface(data)});
  return cases;
}

struct Figures {
  std::string name, failure;  // failure: why no model was made
  std::size_t triangles = 0;
  std::vector<atlas::LevelFigures> levels;
  std::vector<double> meshoptDb;  // per level, meshoptimizer's PSNR at its triangle count; NaN above the dense size
  bool levelsRise = true;
  std::uint64_t backfacing = 0, folded = 0, quads = 0;
  int manifoldCaptures = 0;  // of the three splits
  std::string captureProblem;
  double modelBytes = 0, plyBytes = 0, dracoBytes = 0, buildSeconds = 0, evalSeconds = 0;
};

// Draco's bytes for the mesh, positions quantised to `bits` (connectivity by edgebreaker, the default speed).
double dracoBytes(const Mesh& mesh, int bits) {
  draco::TriangleSoupMeshBuilder builder;
  builder.Start(int(mesh.faceCount()));
  const int position = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    std::array<std::array<float, 3>, 3> corner{};
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = mesh.positions[mesh.face(f)[std::size_t(k)]];
      corner[std::size_t(k)] = {float(p.x), float(p.y), float(p.z)};
    }
    builder.SetAttributeValuesForFace(position, draco::FaceIndex(std::uint32_t(f)), corner[0].data(), corner[1].data(), corner[2].data());
  }
  const std::unique_ptr<draco::Mesh> built = builder.Finalize();
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, bits);
  draco::EncoderBuffer buffer;
  if (!built || !encoder.EncodeMeshToBuffer(*built, &buffer).ok()) return 0;
  return double(buffer.size());
}

// Level 10 from the GPU at every split: the welded capture a closed, oriented 2-manifold or not.
void captureSplits(const atlas::Model& model, Figures& out) {
  const render::ModelLod lod(model);
  const render::AtlasTextures textures(model.atlas);
  render::PatchBuffer patches;
  const Box box = boundingBox(model.base.positions);
  const render::Camera camera = render::Camera::framing(box, 320, 240, {0, 1, -0.8});
  for (const auto& [cpu, halvings] : kSplits) {
    patches.update(lod.patches({render::CpuRefinement::Mode::Level, cpu}, camera, {}));
    const Mesh captured = weldIdenticalPositions(render::AtlasRenderer().capture(
        {{&textures, &patches, {}}}, camera, box, {render::GpuRefinement::Mode::Level, halvings}));
    const MeshTopology t = analyzeTopology(captured);
    const bool clean = t.closed && t.manifold && t.degenerateFaces == 0 && unbalancedEdges(captured) == 0;
    out.manifoldCaptures += clean;
    if (!clean && out.captureProblem.empty())
      out.captureProblem = "--cpu-level " + std::to_string(cpu) + " --gpu-level " + std::to_string(halvings) + ": " +
                           std::to_string(t.nonManifoldEdges) + " non-manifold, " + std::to_string(t.boundaryEdges) + " boundary edges";
  }
}

Figures measure(const Case& c) {
  Figures out{.name = c.name, .triangles = c.dense.faceCount()};
  std::fprintf(stderr, "bench atlas_corpus: %s (%zu triangles)\n", c.name.c_str(), c.dense.faceCount());
  const std::string path = (std::filesystem::temp_directory_path() / "bench_atlas_corpus.isoatlas").string();
  auto start = std::chrono::steady_clock::now();
  std::vector<atlas::Normal16> faceNormals;  // the file does not keep them
  try {
    nlohmann::json figures;
    const atlas::Model built = pipeline::buildModel(c.dense, {.hausdorff = false}, figures);  // as `isoatlas build` builds it
    faceNormals = built.atlas.triangleFaceNormals;
    atlas::writeModel(path, built);
  } catch (const std::exception& e) {
    out.failure = e.what();
    return out;
  }
  out.buildSeconds = since(start);
  out.modelBytes = double(std::filesystem::file_size(path));
  atlas::Model model = atlas::readModel(path);
  model.atlas.triangleFaceNormals = std::move(faceNormals);
  std::filesystem::remove(path);
  out.plyBytes = double(atlas::binaryPlyBytes(c.dense));
  out.dracoBytes = dracoBytes(c.dense, 14);
  const atlas::BackFacingQuads back = atlas::countBackFacingQuads(model.atlas);
  out.backfacing = back.quads, out.quads = back.total;
  out.folded = atlas::countFoldedQuads(model.atlas).quads;

  start = std::chrono::steady_clock::now();
  out.levels = atlas::evaluateLevels(model.base, model.atlas, c.dense, {std::begin(kLevels), std::end(kLevels)});
  out.evalSeconds = since(start);
  const double diagonal = boundingBox(c.dense.positions).diagonal();
  const MeshDistances fromDense(c.dense);
  for (std::size_t i = 0; i < out.levels.size(); ++i) {
    const atlas::LevelFigures& l = out.levels[i];
    if (i > 0 && l.psnrDb < out.levels[i - 1].psnrDb) out.levelsRise = false;
    double seconds = 0, db = std::numeric_limits<double>::quiet_NaN();
    if (l.triangles < c.dense.faceCount())
      if (const Mesh simplified = bench::meshoptSimplify(c.dense, l.triangles, seconds); simplified.faceCount() > 0)
        db = psnrDb(diagonal, fromDense.to(simplified).symmetric());
    out.meshoptDb.push_back(db);
  }
  captureSplits(model, out);
  return out;
}

// Minimum, median and the worst case's name of `value` over the cases that have a model (lower is
// worse unless `higherIsWorse`).
struct Spread {
  double worst = 0, median = 0;
  std::string worstCase;
};
Spread spread(const std::vector<Figures>& cases, const std::function<double(const Figures&)>& value, bool higherIsWorse = false) {
  std::vector<std::pair<double, std::string>> v;
  for (const Figures& f : cases)
    if (f.failure.empty()) v.push_back({higherIsWorse ? -value(f) : value(f), f.name});
  if (v.empty()) return {};
  std::sort(v.begin(), v.end());
  const double sign = higherIsWorse ? -1 : 1;
  return {sign * v.front().first, sign * v[v.size() / 2].first, v.front().second};
}

// The largest gap to meshoptimizer over the levels below the dense size (dB; 0 for none).
double largestGap(const Figures& f) {
  double gap = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < f.levels.size(); ++i)
    if (std::isfinite(f.meshoptDb[i])) gap = std::max(gap, std::min(f.meshoptDb[i], kExactDb) - std::min(f.levels[i].psnrDb, kExactDb));
  return std::isfinite(gap) ? gap : 0.0;
}

// The distribution of every figure over the cases with a model among `cases`, as JSON lines under
// `label` (the worst case's name on stderr).
void reportDistribution(const std::string& label, const std::vector<Figures>& cases) {
  std::size_t made = 0, atFloor = 0, rising = 0, capturesClean = 0, noBackfacing = 0, noFolds = 0;
  for (const Figures& f : cases) {
    if (!f.failure.empty()) continue;
    ++made;
    atFloor += f.levels.back().psnrDb >= kWorstTargetDb;
    rising += f.levelsRise;
    capturesClean += f.manifoldCaptures == 3;
    noBackfacing += f.backfacing == 0;
    noFolds += f.folded == 0;
  }
  const std::string group = label + " (" + std::to_string(made) + " cases with a model, of " + std::to_string(cases.size()) + ")";
  auto row = [&](const std::string& metric, const Spread& s, const std::string& peer, double target) {
    std::fprintf(stderr, "bench atlas_corpus: %s: %s: worst %.4g (%s), median %.4g\n", group.c_str(), metric.c_str(), s.worst,
                 s.worstCase.c_str(), s.median);
    bench::report("atlas_corpus", group, metric + ", worst case", s.worst, peer, target, false);
    bench::report("atlas_corpus", group, metric + ", median", s.median, peer, target, false);
  };
  row("PSNR at level 10 (dB)", spread(cases, [](const Figures& f) { return f.levels.back().psnrDb; }),
      "the issue's target (worst 55, median 65)", kMedianTargetDb);
  row("PSNR by RMS at level 10 (dB)", spread(cases, [](const Figures& f) { return f.levels.back().psnrRmsDb; }),
      "PSNR by the largest distance's median target", kMedianTargetDb);
  row("gap to meshoptimizer, largest over the levels below the dense size (dB)", spread(cases, largestGap, true),
      "the issue's target (at most)", 0);
  row("texel quads folded (share)", spread(cases, [](const Figures& f) { return double(f.folded) / double(f.quads); }, true),
      "the issue's target", 0);
  row("texel quads facing against the shading normals (share)",
      spread(cases, [](const Figures& f) { return double(f.backfacing) / double(f.quads); }, true), "the issue's target for folds", 0);
  row("model bytes over the binary PLY", spread(cases, [](const Figures& f) { return f.modelBytes / f.plyBytes; }, true),
      "the issue's target at the median (at most)", 1);
  const Spread model = spread(cases, [](const Figures& f) { return f.modelBytes / f.plyBytes; }, true),
               draco = spread(cases, [](const Figures& f) { return f.dracoBytes / f.plyBytes; }, true);
  std::fprintf(stderr, "bench atlas_corpus: %s: Draco's bytes over the binary PLY: worst %.4g (%s), median %.4g\n", group.c_str(), draco.worst,
               draco.worstCase.c_str(), draco.median);
  bench::report("atlas_corpus", group, "bytes over the binary PLY, median", model.median, "Draco 1.5, 14-bit positions", draco.median);
  bench::report("atlas_corpus", group, "cases at least 55 dB at level 10", double(atFloor), "cases", double(made), false);
  bench::report("atlas_corpus", group, "cases whose levels rise", double(rising), "cases", double(made), false);
  bench::report("atlas_corpus", group, "cases whose level-10 captures are closed 2-manifolds at all three splits", double(capturesClean),
                "cases", double(made), false);
  bench::report("atlas_corpus", group, "cases without folded texel quads", double(noFolds), "cases", double(made), false);
  bench::report("atlas_corpus", group, "cases without texel quads facing against the shading normals", double(noBackfacing), "cases",
                double(made), false);
}

// Every case as a row of a table (markdown, on stderr).
void printTable(const std::vector<Figures>& cases) {
  std::fprintf(stderr, "\n| case | triangles | level 10 dB (RMS) | gap to meshopt per level (dB) | levels rise | folded quads (against shading normals) | captures | model/PLY | Draco/PLY | build s |\n"
                       "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
  for (const Figures& f : cases) {
    if (!f.failure.empty()) {
      std::fprintf(stderr, "| %s | %zu | no model: %s |  |  |  |  |  |  |  |\n", f.name.c_str(), f.triangles, f.failure.c_str());
      continue;
    }
    std::string gaps;
    for (std::size_t i = 0; i < f.levels.size(); ++i)
      if (std::isfinite(f.meshoptDb[i])) {
        char g[48];
        std::snprintf(g, sizeof g, "%sL%d %+.1f", gaps.empty() ? "" : ", ", f.levels[i].level,
                      std::min(f.meshoptDb[i], kExactDb) - std::min(f.levels[i].psnrDb, kExactDb));
        gaps += g;
      }
    std::fprintf(stderr, "| %s | %zu | %.1f (%.1f) | %s | %s | %.2f %% (%.2f %%) | %d/3%s | %.2f | %.2f | %.1f |\n", f.name.c_str(), f.triangles,
                 f.levels.back().psnrDb, f.levels.back().psnrRmsDb, gaps.empty() ? "none below the dense size" : gaps.c_str(),
                 f.levelsRise ? "yes" : "no", 100.0 * double(f.folded) / double(f.quads), 100.0 * double(f.backfacing) / double(f.quads),
                 f.manifoldCaptures,
                 f.captureProblem.empty() ? "" : (" (" + f.captureProblem + ")").c_str(), f.modelBytes / f.plyBytes,
                 f.dracoBytes / f.plyBytes, f.buildSeconds);
  }
}

// Level-10 PSNR by both measures over the cases, sorted by the largest distance's, with the floor.
void plot(const std::vector<Figures>& cases) {
  std::vector<const Figures*> sorted;
  for (const Figures& f : cases)
    if (f.failure.empty()) sorted.push_back(&f);
  std::sort(sorted.begin(), sorted.end(), [](const Figures* a, const Figures* b) { return a->levels.back().psnrDb < b->levels.back().psnrDb; });
  PlotSeries largest{"level 10, largest distance", {}, {}, 0, false}, rms{"level 10, RMS distance", {}, {}, 0, true},
      floor{"the floor (55 dB)", {}, {}, 1, true}, median{"the median target (65 dB)", {}, {}, 2, true};
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    largest.x.push_back(double(i)), largest.y.push_back(sorted[i]->levels.back().psnrDb);
    rms.x.push_back(double(i)), rms.y.push_back(sorted[i]->levels.back().psnrRmsDb);
  }
  floor.x = median.x = {0, double(std::max<std::size_t>(1, sorted.size()) - 1)};
  floor.y = {kWorstTargetDb, kWorstTargetDb}, median.y = {kMedianTargetDb, kMedianTargetDb};
  const std::filesystem::path file = std::filesystem::path(ISOATLAS_BENCH_DIR) / "atlas_corpus.png";
  writePng(file.string(), linePlot({largest, rms, floor, median},
                                   {.title = "The model at level 10 over the corpus (CGAL's distance to the dense mesh)",
                                    .xLabel = "case, sorted by the largest distance's PSNR",
                                    .yLabel = "PSNR (dB)"}));
  std::fprintf(stderr, "bench atlas_corpus: wrote %s\n", file.c_str());
}

}  // namespace

// bench_atlas_corpus [DATA]
int main(int argc, char** argv) {
  const std::string data = argc > 1 ? argv[1] : "data";
  const auto context = gl::Context::headless();
  const std::vector<Case> cases = corpus(data, envCount("ISOATLAS_BENCH_CORPUS_MOST_TRIANGLES", 500000),
                                         envCount("ISOATLAS_BENCH_CORPUS_WHITE_MATTER", 1) != 0,
                                         std::getenv("ISOATLAS_BENCH_CORPUS_ONLY") ? std::getenv("ISOATLAS_BENCH_CORPUS_ONLY") : "");
  std::vector<Figures> figures;
  for (const Case& c : cases) {
    figures.push_back(measure(c));
  }
  reportDistribution("corpus", figures);
  std::vector<Figures> large;
  for (const Figures& f : figures)
    if (f.triangles >= 5000) large.push_back(f);
  reportDistribution("corpus, at least 5,000 triangles", large);
  printTable(figures);
  plot(figures);
  return 0;
}
