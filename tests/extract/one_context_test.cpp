// The stages in one GL context, as `isoatlas run` and the viewer run them: a GPU solver, marching
// cubes straight from its pages and a render, with no second context and no program compiled twice.
#include <gtest/gtest.h>

#include <cmath>

#include "core/gl/context.h"
#include "core/mesh_topology.h"
#include "extract/extract_surface.h"
#include "levelset/level_set.h"
#include "tests/gl_context.h"
#include "tests/test_util.h"
#include "render/mesh_render.h"

namespace isoatlas {
namespace {

TEST(OneContext, SolverExtractionFromItsPagesAndRender) {
  gl::Context& ctx = test::glContext();
  const int contexts = gl::Context::made();
  const Volume image = test::fieldVolume({40, 36, 24}, [](double x, double y, double z) {
    return std::sqrt((x - 20) * (x - 20) + (y - 17) * (y - 17) + (z - 12) * (z - 12)) < 9 ? 100.0 : 20.0;
  });
  levelset::LevelSet ls(image, {100, 40, 0.8f}, {.backend = levelset::Backend::Gpu});
  ls.addSphere({20, 17, 12}, 3);
  ls.run({.maxIterations = 150});
  extract::ExtractStats stats;
  const Mesh surface = extract::extractLevelSet(ls, {.backend = levelset::Backend::Gpu}, &stats);
  EXPECT_EQ(stats.path, "gpu pages");
  const MeshTopology t = analyzeTopology(surface);
  EXPECT_TRUE(t.closed && t.manifold);
  EXPECT_EQ(t.genus, 0);
  Image picture = render::renderMesh(surface, {.width = 64, .height = 48});
  // The sphere covers the middle of the picture and leaves the corner white.
  EXPECT_NE(picture.at(32, 24)[2], 255);
  EXPECT_EQ(picture.at(0, 0)[0], 255);

  // Again: every program is cached, and the solver still steps after the extraction and the render
  // changed the context's bindings.
  const int compiled = ctx.programsCompiled();
  const Mesh again = extract::extractLevelSet(ls, {.backend = levelset::Backend::Gpu});
  render::renderMesh(again, {.width = 64, .height = 48});
  ls.step();
  EXPECT_EQ(ctx.programsCompiled(), compiled);
  EXPECT_EQ(again.faceCount(), surface.faceCount());
  EXPECT_EQ(gl::Context::made(), contexts) << "a stage opened a context of its own";
  gl::checkErrors("one context");
}

}  // namespace
}  // namespace isoatlas
