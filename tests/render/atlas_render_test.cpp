// The tessellated atlas against its CPU twin and the crack-free invariant: with no GPU refinement
// the GPU makes exactly the CPU's mesh (the same triangles, by their corners' positions); with any CPU and GPU
// levels and cameras, the captured triangles welded by exact position are an oriented 2-manifold
// (every directed edge once, with its twin; no triangle repeating a vertex), closed on a closed
// model, and open only along the model's own boundary on one with holes; each added GPU halving
// quadruples a base tile's triangles.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "atlas/make_atlas.h"
#include "atlas/reconstruct.h"
#include "atlas/stamp_detail.h"
#include "atlas/tile_sides.h"
#include "core/mesh_topology.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"
#include "tests/gl_context.h"
#include "tests/multires/mesh_shapes.h"
#include "tests/render/test_models.h"
#include "render/atlas_render.h"
#include "render/cpu_level.h"
#include "render/model_lod.h"

namespace isoatlas::render {
namespace {

using test::buildModel;
const atlas::Model& torus() {
  static const atlas::Model m = buildModel(test::torusMesh(48, 24), 0.04, 17);
  return m;
}
// A plane with two square holes: three boundary loops.
const atlas::Model& holedPlane() {
  static const atlas::Model m = buildModel(test::gridMesh(30, 24, [](int i, int j) {
    return (i >= 6 && i < 10 && j >= 6 && j < 10) || (i >= 18 && i < 23 && j >= 12 && j < 16);
  }), 0.05, 9);
  return m;
}

// The torus with a bar stamped on its outer equator: detail charts of 65 texels (4 per chart texel).
const atlas::Model& stampedTorus() {
  static const atlas::Model m = [] {
    atlas::Model out = torus();
    Image bar(24, 16, 1);
    for (int y = 5; y < 11; ++y)
      for (int x = 3; x < 21; ++x) *bar.at(x, y) = 255;
    atlas::stampDetail(out.base, out.atlas, {.image = bar, .at = {4.2, 0.5, 0.3}, .radius = 1.2, .depth = 0.15, .detailSize = 65});
    return out;
  }();
  return m;
}

struct Scene {
  const atlas::Model& model;
  ModelLod lod{model};
  AtlasTextures textures{model.atlas};
  PatchBuffer patches;
  Box box = boundingBox(model.atlas.positions.empty() ? std::vector<Vec3>{} : model.base.positions);
  explicit Scene(const atlas::Model& m) : model(m) {}
  // Seen from in front and above, turned about the vertical.
  Camera camera(double turn = 0) const { return Camera::framing(box, 320, 240, {0, 1, -0.8}).turned(turn); }
  Mesh capture(const CpuRefinement& cpu, const GpuRefinement& gpu, const Camera& c, multires::AdaptiveMesh* cpuMesh = nullptr) {
    patches.update(lod.patches(cpu, c, {}));
    if (cpuMesh) *cpuMesh = lod.refined(cpu, c, {});
    return AtlasRenderer().capture({{&textures, &patches, {}}}, c, box, gpu);
  }
};

std::array<float, 3> asFloats(const Vec3& p) { return {float(p.x), float(p.y), float(p.z)}; }

std::set<std::array<float, 3>> vertexSet(const Mesh& m) {
  std::set<std::array<float, 3>> s;
  for (const Vec3& p : m.positions) s.insert(asFloats(p));
  return s;
}

// Each triangle by its corners' positions, turned to start at its least corner (its orientation kept):
// two meshes with the same set drew the same surface, whatever their vertex numbering.
using Triangle = std::array<std::array<float, 3>, 3>;
std::multiset<Triangle> triangleSet(const Mesh& m) {
  std::multiset<Triangle> s;
  for (std::size_t f = 0; f < m.faceCount(); ++f) {
    const auto c = m.face(f);
    Triangle t{asFloats(m.positions[c[0]]), asFloats(m.positions[c[1]]), asFloats(m.positions[c[2]])};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    s.insert(t);
  }
  return s;
}

// At CPU level 0 each tile is drawn with its centre, as CPU level 1 has it (a tile in one cell would
// be cut along a diagonal of the driver's choosing, which can fold over a neighbour).
TEST(AtlasRender, WithoutGpuRefinementTheGpuMakesTheCpuMesh) {
  test::glContext();
  Scene scene(torus());
  for (int level = 0; level <= scene.lod.maxLevel(); ++level) {
    const int drawn = std::max(level, 1);
    multires::AdaptiveMesh cpu = scene.lod.refined({CpuRefinement::Mode::Level, drawn}, scene.camera(), {});
    const Mesh gpu = weldIdenticalPositions(scene.capture({CpuRefinement::Mode::Level, level}, {GpuRefinement::Mode::Level, 0}, scene.camera()));
    const Mesh cpuMesh = cpu.triangles();
    ASSERT_TRUE(gpu.allFacesHave(3) && cpuMesh.allFacesHave(3));
    EXPECT_EQ(triangleSet(gpu), triangleSet(cpuMesh)) << "level " << level;
    // And the uniform level is the atlas's reconstruction of that level.
    EXPECT_EQ(vertexSet(gpu), vertexSet(atlas::reconstructLevel(scene.model.base, scene.model.atlas, drawn))) << "level " << level;
  }
}

// From the tile with its centre (4 triangles) on, each halving quadruples a tile's triangles.
TEST(AtlasRender, EachGpuHalvingQuadruplesATile) {
  test::glContext();
  Scene scene(torus());
  const std::size_t tiles = scene.model.base.tiles.size();
  for (int halvings = 0; halvings <= 4; ++halvings) {
    const Mesh gpu = scene.capture({CpuRefinement::Mode::Level, 0}, {GpuRefinement::Mode::Level, halvings}, scene.camera());
    const std::size_t perTile = halvings == 0 ? 4 : 2 * (std::size_t(1) << (2 * halvings));
    EXPECT_EQ(gpu.faceCount(), tiles * perTile) << halvings << " halvings";
  }
}

// Texel positions on tile sides no other tile shares: the model's own boundary.
std::set<std::array<float, 3>> openSideTexels(const atlas::Model& model) {
  std::set<std::array<float, 3>> out;
  const auto across = atlas::sidesAcross(model.base);
  const std::uint32_t n = model.chartSize;
  for (std::uint32_t t = 0; t < across.size(); ++t)
    for (int side = 0; side < 4; ++side)
      if (across[t][std::size_t(side)].tile == atlas::kNoTile)
        for (std::uint32_t m = 0; m < n; ++m) {
          const auto x = atlas::sideTexel(side, m, n);
          out.insert(asFloats(model.atlas.position(t, x[0], x[1])));
        }
  return out;
}

// Captured triangles welded by exact position have oriented 2-manifold edges: no triangle names a
// vertex twice, no edge has three faces or two running the same way (a fold), and an edge with one
// face (a crack) lies only on the model's own boundary; so the capture is closed exactly where the
// model is.
void expectOrientedManifold(const Mesh& welded, const std::set<std::array<float, 3>>& boundary) {
  const MeshTopology t = analyzeTopology(welded);
  ASSERT_EQ(t.degenerateFaces, 0u) << t.firstProblem;
  ASSERT_EQ(t.nonManifoldEdges, 0u) << t.firstProblem;
  ASSERT_TRUE(t.oriented) << "a fold: two triangles run the same way along an edge";
  std::size_t open = 0;
  for (const auto& [edge, balance] : directedEdgeBalance(welded)) {
    if (balance == 0) continue;
    ++open;
    const Vec3 &a = welded.positions[edge.first], &b = welded.positions[edge.second];
    ASSERT_TRUE(boundary.count(asFloats(a)) && boundary.count(asFloats(b)))
        << "a crack: the edge from " << a.x << ", " << a.y << ", " << a.z << " to " << b.x << ", " << b.y << ", " << b.z << " has no twin";
  }
  if (boundary.empty()) EXPECT_EQ(open, 0u);
  else EXPECT_GT(open, 0u);
}

void expectCrackFree(Scene& scene, int cases, unsigned seed) {
  const auto boundary = openSideTexels(scene.model);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int i = 0; i < cases; ++i) {
    Camera c = scene.camera(unit(rng) * 6.3);
    // Closer in, up or down, narrower: the screen sizes of the tiles vary over the model.
    c.eye = c.target + (c.eye - c.target) * (0.35 + unit(rng)) + Vec3{0, 0, (unit(rng) - 0.5) * scene.box.diagonal()};
    c.fovDegrees = 20 + 40 * unit(rng);
    const CpuRefinement cpu = rng() % 2 ? CpuRefinement{CpuRefinement::Mode::Level, int(rng() % (scene.lod.maxLevel() + 1))}
                                        : CpuRefinement{CpuRefinement::Mode::Pixels, 0, 0.2 + 4 * unit(rng)};
    const GpuRefinement gpu = rng() % 2 ? GpuRefinement{GpuRefinement::Mode::Level, int(rng() % 4)}
                                        : GpuRefinement{GpuRefinement::Mode::Pixels, 0, 2 + 30 * unit(rng)};
    SCOPED_TRACE("case " + std::to_string(i) + ": cpu mode " + std::to_string(int(cpu.mode)) + " level " + std::to_string(cpu.level) +
                 " error " + std::to_string(cpu.pixels) + ", gpu mode " + std::to_string(int(gpu.mode)) + " halvings " +
                 std::to_string(gpu.halvings) + " pixels " + std::to_string(gpu.pixels));
    multires::AdaptiveMesh cpuMesh = scene.lod.refined(cpu, c, {});
    const Mesh gpuMesh = weldIdenticalPositions(scene.capture(cpu, gpu, c, &cpuMesh));
    expectOrientedManifold(gpuMesh, boundary);
    if (::testing::Test::HasFatalFailure()) return;
    // The GPU refines above the CPU: every CPU vertex is one of its vertices (on tiles with a detail
    // chart the GPU reads that chart, the CPU the coarser one).
    if (!scene.model.atlas.details.empty()) continue;
    const auto gpuVertices = vertexSet(gpuMesh);
    for (const Vec3& p : cpuMesh.triangles().positions) ASSERT_TRUE(gpuVertices.count(asFloats(p))) << "a CPU vertex is missing";
    if (::testing::Test::HasFatalFailure()) return;
  }
}

TEST(AtlasRender, CrackFreeOverRandomLevelsAndCameras) {
  test::glContext();
  Scene scene(torus());
  expectCrackFree(scene, 40, 7);
}

TEST(AtlasRender, OnlyTheModelsOwnBoundaryStaysOpen) {
  test::glContext();
  Scene scene(holedPlane());
  ASSERT_EQ(analyzeTopology(atlas::reconstructLevel(scene.model.base, scene.model.atlas, 0)).boundaryLoops, 3u);
  // A vertex in too few tiles: where a tile in one tessellation cell, cut along its other diagonal,
  // would fold over its neighbour (atlas_common.glsl's innerSpacing). Without one, this model no
  // longer guards that case.
  ASSERT_GT(multires::shortVertices(scene.model.base), 0u);
  expectCrackFree(scene, 25, 3);
}

TEST(AtlasRender, DetailChartsRefineTheirTilesWithoutCracks) {
  test::glContext();
  Scene scene(stampedTorus());
  ASSERT_FALSE(scene.model.atlas.details.empty());
  expectCrackFree(scene, 30, 5);
  // The chart's finest level, then two GPU halvings: the stamped tiles reach every texel of their
  // detail charts (those on a border with a tile without one excepted: the chart's there), the
  // other tiles stay at their charts' texels. Every vertex is one of the finest reconstruction's.
  const Camera c = scene.camera();
  const Mesh gpu = weldIdenticalPositions(scene.capture({CpuRefinement::Mode::Level, scene.lod.maxLevel()}, {GpuRefinement::Mode::Level, 2}, c));
  const auto vertices = vertexSet(gpu);
  for (const atlas::DetailChart& d : scene.model.atlas.details)
    for (std::uint32_t j = 1; j + 1 < d.size; ++j)
      for (std::uint32_t i = 1; i + 1 < d.size; ++i)
        ASSERT_TRUE(vertices.count(asFloats(d.position(i, j)))) << "tile " << d.tile << " texel " << i << ", " << j;
  const auto finest = vertexSet(atlas::reconstructLevel(scene.model.base, scene.model.atlas, atlas::maxLevel(scene.model.atlas)));
  for (const auto& p : vertices) ASSERT_TRUE(finest.count(p));
  // A border with a tile without detail is cut at that tile's texels only: no triangle there
  // collapses to a sliver between two reads of one texel.
  EXPECT_EQ(analyzeTopology(gpu).degenerateFaces, 0u);
}

// The CPU mesh kept from view to view (welds where the view allows, splits where it asks) ends
// where a mesh refined for the last view alone would be bound to: nothing left to split or weld
// at the error asked; and its patches draw without cracks.
TEST(AtlasRender, AViewToTheNextBySplitsAndWelds) {
  test::glContext();
  Scene scene(torus());
  multires::AdaptiveMesh mesh = scene.lod.start();
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> unit(0, 1);
  std::size_t welds = 0;
  const auto boundary = openSideTexels(scene.model);
  for (int step = 0; step < 12; ++step) {
    Camera c = scene.camera(unit(rng) * 6.3);
    c.eye = c.target + (c.eye - c.target) * (0.3 + 1.5 * unit(rng));
    const CpuRefinement cpu{CpuRefinement::Mode::Pixels, 0, 0.3 + 3 * unit(rng)};
    const CpuFigures f = scene.lod.adapt(mesh, cpu, c, {});
    welds += f.welds;
    SCOPED_TRACE("step " + std::to_string(step));
    const MeshTopology t = analyzeTopology(mesh.triangles());
    ASSERT_TRUE(t.closed && t.manifold) << t.firstProblem;
    const EdgeError onScreen = [&](const Vec3& sample, const Vec3& chord) { return norm(sample - chord) * c.pixelsPerUnit(chord); };
    multires::AdaptiveMesh again = mesh;
    EXPECT_EQ(refineToError(again, onScreen, cpu.pixels), 0u) << "an edge the view asks to split is left";
    EXPECT_EQ(coarsenToError(again, onScreen, cpu.pixels), 0u) << "a vertex the view allows to weld is left";
    scene.patches.update(scene.lod.patchesOf(mesh));
    const Mesh gpu = weldIdenticalPositions(AtlasRenderer().capture({{&scene.textures, &scene.patches, {}}}, c, scene.box,
                                                                    {GpuRefinement::Mode::Pixels, 0, 6}));
    expectOrientedManifold(gpu, boundary);
  }
  EXPECT_GT(welds, 100u) << "views farther than the last coarsen the mesh";
}

TEST(AtlasRender, PatchBufferSendsOnlyWhatChanged) {
  test::glContext();
  Scene scene(torus());
  PatchBuffer buffer;
  std::vector<GpuPatch> patches = scene.lod.patches({CpuRefinement::Mode::Level, 3}, scene.camera(), {});
  EXPECT_EQ(buffer.update(patches), patches.size() * sizeof(GpuPatch));
  EXPECT_EQ(buffer.update(patches), 0u);
  patches[5].size ^= 1u << 24;
  patches[9].sides ^= 1u;
  EXPECT_EQ(buffer.update(patches), 5 * sizeof(GpuPatch));
  EXPECT_EQ(buffer.buffer().read<GpuPatch>(patches.size()), patches);
}

TEST(AtlasRender, PictureShowsTheModelAndItsTileBorders) {
  test::glContext();
  Scene scene(torus());
  scene.patches.update(scene.lod.patches({CpuRefinement::Mode::Level, 2}, scene.camera(0.5), {}));
  const gl::Framebuffer fbo(320, 240);
  DrawStyle style;
  style.wireframe = true;
  const FrameFigures f = AtlasRenderer().draw({{&scene.textures, &scene.patches, {}}}, scene.camera(0.5), scene.box,
                                              {GpuRefinement::Mode::Level, 1}, style, fbo);
  // Level 2: one patch a tile, its centre and side midpoints on the CPU; one halving makes it 4 x 4.
  EXPECT_EQ(f.patches, scene.model.base.tiles.size());
  EXPECT_EQ(f.triangles, f.patches * 32);
  const Image image = fbo.readImage();
  std::size_t background = 0, brown = 0, blue = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const auto* p = image.at(x, y);
      background += p[0] == 255 && p[1] == 255 && p[2] == 255;
      brown += p[0] > 110 && p[0] < 170 && p[1] > 40 && p[1] < 90 && p[2] < 40;
      blue += p[2] > 150 && p[0] < 60;
    }
  EXPECT_GT(background, image.width * image.height / 5u);
  EXPECT_LT(background, image.width * image.height * 9 / 10u);
  EXPECT_GT(brown, 100u) << "tile borders drawn brown";
  EXPECT_GT(blue, 100u) << "tile interiors drawn blue";
  // Without the wireframe the surface goes to the fragments without the geometry stage (in draws
  // of a few patches on llvmpipe): the same triangles cover the same pixels.
  const FrameFigures plain = AtlasRenderer().draw({{&scene.textures, &scene.patches, {}}}, scene.camera(0.5), scene.box,
                                                  {GpuRefinement::Mode::Level, 1}, {}, fbo);
  EXPECT_EQ(plain.triangles, f.triangles);
  const Image shaded = fbo.readImage();
  auto white = [](const Image& i, int x, int y) { return i.at(x, y)[0] == 255 && i.at(x, y)[1] == 255 && i.at(x, y)[2] == 255; };
  std::size_t same = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) same += white(image, x, y) == white(shaded, x, y);
  EXPECT_EQ(same, std::size_t(image.width) * std::size_t(image.height));
}

}  // namespace
}  // namespace isoatlas::render
