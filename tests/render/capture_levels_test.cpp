// The model as a clean surface at every level, as drawn and as reconstructed, on real meshes
// (bunny00, a marching-cubes surface of a label volume, and corpus meshes through their model files):
// for every CPU level and every number of
// GPU halvings up to the chart's finest (CPU level c + 2 halvings <= the finest level), the captured
// triangles, welded by exact position only, are a closed oriented 2-manifold (every directed edge
// once and with its twin, no triangle repeating a vertex); from an even CPU level, over exactly the
// vertices and the triangle count of the CPU's reconstruction of level c + 2 halvings (eval
// --out-mesh-level), which is one at every level too.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "atlas/evaluate_levels.h"
#include "atlas/model_file.h"
#include "atlas/reconstruct.h"
#include "core/mesh_io.h"
#include "core/mesh_topology.h"
#include "extract/extract_surface.h"
#include "render/atlas_render.h"
#include "render/model_lod.h"
#include "tests/gl_context.h"
#include "tests/render/test_models.h"
#include "tests/test_util.h"

namespace isoatlas::render {
namespace {

using Positions = std::set<std::array<float, 3>>;
Positions positionsOf(const Mesh& m) {
  Positions s;
  for (const Vec3& p : m.positions) s.insert({float(p.x), float(p.y), float(p.z)});
  return s;
}

// Welded by exact position, closed, oriented, 2-manifold: what `render --capture` and
// `eval --out-mesh-level` must give on a closed model.
void expectClosedOrientedManifold(const Mesh& welded, const std::string& what) {
  const MeshTopology t = analyzeTopology(welded);
  EXPECT_EQ(t.degenerateFaces, 0u) << what << ": a triangle repeats a vertex; " << t.firstProblem;
  EXPECT_EQ(t.nonManifoldEdges, 0u) << what << ": " << t.firstProblem;
  EXPECT_EQ(t.boundaryEdges, 0u) << what << ": not closed";
  EXPECT_EQ(unbalancedEdges(welded), 0u) << what << ": a directed edge without its twin, or used twice";
}

// Every split of every level: the capture against the CPU's reconstruction of the same level.
void expectEveryLevelClean(const atlas::Model& model) {
  test::glContext();
  const ModelLod lod(model);
  const AtlasTextures textures(model.atlas);
  PatchBuffer patches;
  const Box box = boundingBox(model.base.positions);
  const Camera camera = Camera::framing(box, 320, 240, {0, 1, -0.8});
  const int top = atlas::maxLevel(model.chartSize);
  std::vector<Mesh> reconstructed;
  for (int level = 0; level <= top; ++level) {
    reconstructed.push_back(weldIdenticalPositions(atlas::reconstructLevel(model.base, model.atlas, level)));
    expectClosedOrientedManifold(reconstructed.back(), "eval's level " + std::to_string(level));
  }
  for (int cpu = 0; cpu <= top; ++cpu)
    for (int halvings = 0; cpu + 2 * halvings <= top; ++halvings) {
      const int level = cpu + 2 * halvings;
      const std::string what = "level " + std::to_string(level) + " (--cpu-level " + std::to_string(cpu) + " --gpu-level " +
                               std::to_string(halvings) + ")";
      patches.update(lod.patches({CpuRefinement::Mode::Level, cpu}, camera, {}));
      const Mesh captured = weldIdenticalPositions(AtlasRenderer().capture({{&textures, &patches, {}}}, camera, box,
                                                                          {GpuRefinement::Mode::Level, halvings}));
      expectClosedOrientedManifold(captured, what);
      // From an even CPU level (a grid of quads in each tile) the GPU's halvings make the uniform level
      // L; level 0 is drawn with each tile's centre, as level 1 has it (atlas_common.glsl's innerSpacing).
      if (cpu % 2 == 0) {
        const Mesh& drawn = reconstructed[std::max(level, 1)];
        EXPECT_EQ(captured.faceCount(), drawn.faceCount()) << what;
        EXPECT_EQ(captured.vertexCount(), drawn.vertexCount()) << what;
        EXPECT_TRUE(positionsOf(captured) == positionsOf(drawn)) << what << ": the capture's vertices are not the reconstruction's";
      }
      if (::testing::Test::HasFailure()) return;
    }
}

TEST(CaptureLevels, Bunny00IsAClosedManifoldAtEveryLevelAndSplit) {
  const std::filesystem::path file = std::filesystem::path(ISOATLAS_DATA) / "meshes" / "bunny00.off";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "run scripts/fetch-data for " << file;
  // About 380 tiles of 17 texels: levels 0 to 8, 190,000 triangles at the finest, made by draws of
  // more than 65,536 vertices where the renderer does not split them (render/atlas_render.cpp).
  expectEveryLevelClean(test::buildModel(readMesh(file.string()), 0.01, 17));
}

// Corpus meshes (bench/atlas_corpus runs them all) built as `isoatlas build` builds them and read
// back from their model files, the quantised atlas a user gets (cow and femur had texels joined by
// their codes: atlas/separate_codes.h): clean at every level and split, and nearer the dense mesh
// level by level: by the RMS distance every even level is nearer than the one below, and level 10
// is at least 6 dB nearer by the largest distance than the base mesh (a level 10 sampled without the
// parametrisation's history would lie on the base mesh's triangles).
TEST(CaptureLevels, CorpusModelsFromTheirFilesAreCleanAndNearerAtEveryLevel) {
  for (const char* name : {"cow", "femur"}) {
    const std::filesystem::path file = std::filesystem::path(ISOATLAS_DATA) / "meshes" / (std::string(name) + ".off");
    if (!std::filesystem::exists(file)) GTEST_SKIP() << "run scripts/fetch-data for " << file;
    const Mesh dense = dropUnusedVertices(readMesh(file.string()));  // as `isoatlas build` prepares it
    atlas::Model built{.chartSize = 33, .base = multires::simplifyStellar(dense), .atlas = {}, .dense = {}};
    multires::pairTriangles(built.base, dense);
    built.atlas = atlas::makeAtlas(dense, built.base, 33);
    built.base.denseTriangle.clear(), built.base.denseBary.clear();
    const std::string path = (test::scratchDir() / (std::string(name) + ".isoatlas")).string();
    atlas::writeModel(path, built);
    const atlas::Model model = atlas::readModel(path);
    SCOPED_TRACE(name);
    expectEveryLevelClean(model);
    const std::vector<atlas::LevelFigures> levels = atlas::evaluateLevels(model.base, model.atlas, dense, {0, 2, 4, 6, 8, 10});
    for (std::size_t i = 1; i < levels.size(); ++i)
      EXPECT_GT(levels[i].psnrRmsDb, levels[i - 1].psnrRmsDb) << "level " << levels[i].level << " by RMS";
    EXPECT_GE(levels.back().psnrDb, levels.front().psnrDb + 6) << "level 10 by the largest distance";
  }
}

// A label volume (label 1 a ball, label 2 a box through it and a handle joining them), its mask of
// labels > 0 through marching cubes: the staircase, creases and a handle of a real segmentation.
TEST(CaptureLevels, ALabelVolumesSurfaceIsAClosedManifoldAtEveryLevelAndSplit) {
  const Volume labels = test::fieldVolume({40, 32, 28}, [](double x, double y, double z) {
    const bool ball = (x - 12) * (x - 12) + (y - 14) * (y - 14) + (z - 14) * (z - 14) < 64;
    const bool box = x > 14 && x < 24 && y > 10 && y < 18 && z > 9 && z < 19;
    const double ring = std::hypot(x - 24, z - 14) - 7;  // a handle from the box round to the ball
    const bool handle = ring * ring + (y - 14) * (y - 14) < 4 && x > 16;
    return ball ? 1.0 : box || handle ? 2.0 : 0.0;
  });
  Volume mask = Volume::zeros(labels.dims, ScalarType::UInt8);
  for (std::size_t n = 0; n < labels.voxelCount(); ++n) mask.setValue(n, labels.value(n) > 0 ? 1 : 0);
  const Mesh surface = extract::extractSurface(mask, {.largestComponents = 1});
  ASSERT_GT(surface.faceCount(), 1000u);
  expectEveryLevelClean(test::buildModel(surface, 0.02, 17));
}

}  // namespace
}  // namespace isoatlas::render
