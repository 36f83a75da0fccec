// Extraction against truth: spheres and tori of known area, volume and genus; random fields whose
// every output must be closed, manifold and oriented by analyzeTopology (which shares no code with
// the extractor); masks touching the border; world coordinates through a mirrored frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <optional>
#include <random>
#include <string>

#include "core/error.h"
#include "core/mesh_topology.h"
#include "extract/extract_surface.h"
#include "extract/cpu_marching_cubes.h"
#include "extract/marching_cubes.h"
#include "extract/straddling_blocks.h"
#include "tests/extract/same_mesh.h"
#include "levelset/level_set.h"
#include "tests/gl_context.h"
#include "tests/test_util.h"
#include "tests/thread_count.h"

namespace isoatlas::extract {
namespace {

using test_mesh::expectIdenticalMesh;
using test_mesh::expectSameMesh;

double area(const Mesh& m) {
  double a = 0;
  for (std::size_t f = 0; f < m.faceCount(); ++f) {
    const auto t = m.face(f);
    a += norm(cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]])) / 2;
  }
  return a;
}
double enclosedVolume(const Mesh& m) {  // positive when the normals point out
  double v = 0;
  for (std::size_t f = 0; f < m.faceCount(); ++f) {
    const auto t = m.face(f);
    v += dot(m.positions[t[0]], cross(m.positions[t[1]], m.positions[t[2]])) / 6;
  }
  return v;
}
std::size_t degenerate(const Mesh& m) {
  std::size_t n = 0;
  for (std::size_t f = 0; f < m.faceCount(); ++f) {
    const auto t = m.face(f);
    n += norm(cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]])) < 1e-12;
  }
  return n;
}

void expectClosedManifold(const Mesh& m, long long genus) {
  const MeshTopology t = analyzeTopology(m);
  EXPECT_TRUE(t.closed) << t.firstProblem;
  EXPECT_TRUE(t.manifold) << t.firstProblem;
  EXPECT_TRUE(t.oriented);
  EXPECT_EQ(t.genus, genus);
  EXPECT_EQ(degenerate(m), 0u);
}

TEST(MarchingCubes, SphereAreaVolumeAndGenus) {
  const double R = 14;
  const Volume v = test::fieldVolume({40, 40, 40}, [&](double x, double y, double z) {
    return R - std::sqrt((x - 19.5) * (x - 19.5) + (y - 20.2) * (y - 20.2) + (z - 19.7) * (z - 19.7));
  });
  ExtractStats stats;
  const Mesh m = extractSurface(v, {.iso = 0.0f}, &stats);
  expectClosedManifold(m, 0);
  EXPECT_NEAR(area(m), 4 * M_PI * R * R, 0.01 * 4 * M_PI * R * R);
  EXPECT_NEAR(enclosedVolume(m), 4.0 / 3 * M_PI * R * R * R, 0.01 * 4.0 / 3 * M_PI * R * R * R);
  EXPECT_LT(stats.cellsVisited, stats.cellsTotal) << "blocks away from the surface are skipped";
}

TEST(MarchingCubes, TorusAreaVolumeAndGenus) {
  const double R = 12, r = 5;
  const Volume v = test::fieldVolume({44, 44, 20}, [&](double x, double y, double z) {
    const double q = std::hypot(x - 21.6, y - 21.3) - R;
    return r - std::sqrt(q * q + (z - 9.6) * (z - 9.6));
  });
  const Mesh m = extractSurface(v, {.iso = 0.0f});
  expectClosedManifold(m, 1);
  EXPECT_NEAR(area(m), 4 * M_PI * M_PI * R * r, 0.01 * 4 * M_PI * M_PI * R * r);
  EXPECT_NEAR(enclosedVolume(m), 2 * M_PI * M_PI * R * r * r, 0.01 * 2 * M_PI * M_PI * R * r * r);
}

TEST(MarchingCubes, RandomFieldsAreClosedManifoldAndOriented) {
  // Integer values with an integer isovalue: many corners equal iso exactly.
  std::mt19937 rng(3);
  for (int trial = 0; trial < 30; ++trial) {
    std::uniform_int_distribution<int> value(-3, 3);
    const Volume v = test::fieldVolume({9 + trial % 4, 8, 7 + trial % 3}, [&](double, double, double) { return value(rng); });
    for (float iso : {0.0f, 0.5f, 2.0f}) {
      const Mesh m = extractSurface(v, {.iso = iso});
      if (m.faceCount() == 0) continue;
      const MeshTopology t = analyzeTopology(m);
      ASSERT_TRUE(t.closed && t.manifold && t.oriented) << "trial " << trial << " iso " << iso << ": " << t.firstProblem;
      ASSERT_EQ(degenerate(m), 0u);
      ASSERT_GT(enclosedVolume(m), 0) << "normals point out";
    }
  }
}

TEST(MarchingCubes, EveryCasePatternClosesAcrossNeighbours) {
  // A 3x3x3 grid of +-1 values from all 2^27 patterns is too many; 20000 random ones cover every
  // cell case many times over, with neighbouring cells in every combination.
  std::mt19937 rng(11);
  std::bernoulli_distribution in(0.5);
  for (int trial = 0; trial < 20000; ++trial) {
    std::vector<float> values(27);
    for (float& x : values) x = in(rng) ? 1.0f : -1.0f;
    const MarchingResult r = marchingCubesCpu({{3, 3, 3}, values.data()}, 0.0f);
    if (r.mesh.faceCount() == 0) continue;
    const MeshTopology t = analyzeTopology(r.mesh);
    ASSERT_TRUE(t.closed && t.manifold && t.oriented) << "trial " << trial << ": " << t.firstProblem;
  }
}

// Rows of bits against the rule itself: value x at bit x + 1 when above iso (a value equal to iso, or
// not a number, is outside); the padding bits and every bit past the row 0. Rows long enough to
// cross words, in lengths that leave every remainder of the four-wide compare.
TEST(BitRows, InsideBitsFollowTheRule) {
  std::mt19937 rng(21);
  for (std::size_t n = 0; n < 200; n += 1 + rng() % 7) {
    std::vector<float> values(n);
    for (float& v : values) {
      const unsigned pick = rng() % 10;
      v = pick == 0 ? 0.25f : pick == 1 ? std::nanf("") : float(int(rng() % 2001) - 1000) / 1000.0f;
    }
    const std::size_t words = rowWords(std::int64_t(n)) + 1;
    std::vector<Word> bits(words, ~Word(0));  // every bit set first: each must be written
    insideBits(values.data(), n, 0.25f, bits.data(), words);
    for (std::size_t i = 0; i < words * kWordBits; ++i) {
      const bool inside = i >= 1 && i <= n && values[i - 1] > 0.25f;
      ASSERT_EQ(bitAt(bits.data(), i), unsigned(inside)) << "n " << n << " bit " << i;
    }
  }
}

// The blocks that straddle iso against each block's corners read one by one (outside the grid is
// outside); the CPU path, told no blocks, visits exactly those and gives the same mesh as when told
// them, or told every block.
TEST(StraddlingBlocks, AreTheBlocksWithCornersOnBothSides) {
  std::mt19937 rng(22);
  for (int trial = 0; trial < 40; ++trial) {
    const std::array<std::int64_t, 3> d{1 + std::int64_t(rng() % 140), 1 + std::int64_t(rng() % 12), 1 + std::int64_t(rng() % 12)};
    std::vector<float> values(std::size_t(d[0] * d[1] * d[2]));
    const bool sparse = trial % 2;  // a few inside points, so whole blocks lie outside
    for (float& v : values) v = sparse ? float(rng() % 9 == 0) : float(int(rng() % 5) - 2);
    const Grid grid{d, values.data()};
    const int block = 2 + int(rng() % 8);
    const float iso = sparse ? 0.5f : 0.0f;
    const VisitBlock straddles = straddlingBlocks(grid, iso, block);
    std::int64_t straddling = 0;
    for (std::int64_t bz = 0; bz < blockCount(d[2], block); ++bz)
      for (std::int64_t by = 0; by < blockCount(d[1], block); ++by)
        for (std::int64_t bx = 0; bx < blockCount(d[0], block); ++bx) {
          const BlockCells xs = blockCells(bx, block, d[0]), ys = blockCells(by, block, d[1]), zs = blockCells(bz, block, d[2]);
          bool in = false, out = false;
          for (std::int64_t z = zs.first; z <= zs.last + 1; ++z)
            for (std::int64_t y = ys.first; y <= ys.last + 1; ++y)
              for (std::int64_t x = xs.first; x <= xs.last + 1; ++x) {
                const bool inGrid = x >= 0 && y >= 0 && z >= 0 && x < d[0] && y < d[1] && z < d[2];
                (inGrid && grid.at(x, y, z) > iso ? in : out) = true;
              }
          ASSERT_EQ(straddles(bx, by, bz), in && out) << "trial " << trial << " block " << bx << " " << by << " " << bz;
          straddling += in && out;
        }
    const MarchingResult own = marchingCubesCpu(grid, iso, block), told = marchingCubesCpu(grid, iso, block, straddles),
                         every = marchingCubesCpu(grid, iso, block, [](std::int64_t, std::int64_t, std::int64_t) { return true; });
    EXPECT_EQ(own.cellsVisited, told.cellsVisited);
    EXPECT_LE(own.cellsVisited, every.cellsVisited);
    EXPECT_EQ(straddling > 0, own.cellsVisited > 0);
    if (own.mesh.faceCount() > 0) {  // all of the surface: closed, by the topology's own count
      const MeshTopology t = analyzeTopology(own.mesh);
      EXPECT_TRUE(t.closed && t.manifold && t.oriented) << "trial " << trial << ": " << t.firstProblem;
    }
    for (const MarchingResult* other : {&told, &every}) {
      EXPECT_TRUE(own.mesh.faceVertices == other->mesh.faceVertices) << "trial " << trial;
      EXPECT_TRUE(own.mesh.positions == other->mesh.positions) << "trial " << trial;
    }
  }
}

TEST(ExtractSurface, MaskTouchingTheBorderIsClosedAndSmooth) {
  Volume mask = Volume::zeros({20, 16, 12}, ScalarType::UInt8);
  for (std::int64_t z = 0; z < 12; ++z)
    for (std::int64_t y = 0; y < 10; ++y)
      for (std::int64_t x = 0; x < 20; ++x) mask.setValue(mask.index(x, y, z), 1);  // touches five faces
  ExtractStats stats;
  const Mesh m = extractSurface(mask, {}, &stats);
  EXPECT_TRUE(stats.binaryInput);
  EXPECT_FLOAT_EQ(stats.iso, 0.5f);
  expectClosedManifold(m, 0);
  // The blurred mask at 0.5 encloses about the mask's own volume (20 x 10 x 12 voxels).
  EXPECT_NEAR(enclosedVolume(m), 20.0 * 10 * 12, 0.1 * 20 * 10 * 12);
}

TEST(ExtractSurface, WorldCoordinatesThroughAMirroredFrame) {
  Volume v = test::fieldVolume({24, 24, 24}, [](double x, double y, double z) {
    return 8 - std::sqrt((x - 12) * (x - 12) + (y - 12) * (y - 12) + (z - 12) * (z - 12));
  });
  v.spacing = {0.5, 2.0, 1.0};
  v.origin = {100, -50, 7};
  v.direction.m = {{{-1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};  // x mirrored: det < 0
  const Mesh m = extractSurface(v, {.iso = 0.0f});
  expectClosedManifold(m, 0);
  EXPECT_GT(enclosedVolume(m), 0) << "still outward after the mirror";
  const Box b = boundingBox(m.positions);
  EXPECT_NEAR(b.max.x, 100 - 4 * 0.5, 0.1);   // voxels 4..20 along i map to x = 98 .. 90
  EXPECT_NEAR(b.min.x, 100 - 20 * 0.5, 0.1);
  EXPECT_NEAR(b.min.y, -50 + 4 * 2.0, 0.6);
  EXPECT_NEAR(b.max.z, 7 + 20, 0.3);
  EXPECT_NEAR(enclosedVolume(m), 4.0 / 3 * M_PI * 512 * 0.5 * 2.0, 0.02 * 4.0 / 3 * M_PI * 512);
}

TEST(ExtractSurface, ComponentsAndSmoothing) {
  const Volume v = test::fieldVolume({40, 20, 20}, [](double x, double y, double z) {
    const double a = 6 - std::sqrt((x - 10) * (x - 10) + (y - 10) * (y - 10) + (z - 10) * (z - 10));
    const double b = 3 - std::sqrt((x - 30) * (x - 30) + (y - 10) * (y - 10) + (z - 10) * (z - 10));
    return std::max(a, b);
  });
  ExtractStats stats;
  const Mesh both = extractSurface(v, {.iso = 0.0f});
  EXPECT_EQ(analyzeTopology(both).components, 2u);
  const Mesh largest = extractSurface(v, {.iso = 0.0f, .largestComponents = 1}, &stats);
  EXPECT_EQ(analyzeTopology(largest).components, 1u);
  EXPECT_EQ(stats.componentsRemoved, 1);
  EXPECT_NEAR(enclosedVolume(largest), 4.0 / 3 * M_PI * 216, 0.03 * 4.0 / 3 * M_PI * 216);
  const Mesh smooth = extractSurface(v, {.iso = 0.0f, .largestComponents = 1, .smoothIterations = 10});
  expectClosedManifold(smooth, 0);
  ASSERT_EQ(smooth.vertexCount(), largest.vertexCount());  // smoothing moves vertices, keeps their order
  double moved = 0;
  for (std::size_t i = 0; i < smooth.vertexCount(); ++i) moved = std::max(moved, norm(smooth.positions[i] - largest.positions[i]));
  EXPECT_GT(moved, 1e-3) << "smoothing moved nothing";
  EXPECT_NEAR(enclosedVolume(smooth), enclosedVolume(largest), 0.03 * enclosedVolume(largest)) << "Taubin keeps volume";
}

TEST(MarchingCubesGpu, GivesTheCpuMesh) {
  test::glContext();
  const Volume torus = test::fieldVolume({44, 44, 20}, [](double x, double y, double z) {
    const double q = std::hypot(x - 21.6, y - 21.3) - 12;
    return 5 - std::sqrt(q * q + (z - 9.6) * (z - 9.6));
  });
  ExtractStats cpuStats, gpuStats;
  const Mesh cpu = extractSurface(torus, {.iso = 0.0f}, &cpuStats);
  const Mesh gpu = extractSurface(torus, {.iso = 0.0f, .backend = levelset::Backend::Gpu}, &gpuStats);
  expectSameMesh(cpu, gpu);
  EXPECT_EQ(cpuStats.cellsVisited, gpuStats.cellsVisited);
  expectClosedManifold(gpu, 1);
  // Random fields with exact-iso corners exercise every case. (No case of today's table fans from a
  // centre vertex: chooseApex finds an apex for every polygon of the 256; the centres' code stands by.)
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> value(-2, 2);
  for (int trial = 0; trial < 8; ++trial) {
    // Rows past 62 points cross the CPU's 64-bit words (bit_rows.h) at every offset of a cell.
    const std::int64_t width = trial < 6 ? 13 : 131 + trial;
    const Volume v = test::fieldVolume({width, 11, 9}, [&](double, double, double) { return value(rng); });
    expectSameMesh(extractSurface(v, {.iso = 0.0f}), extractSurface(v, {.iso = 0.0f, .backend = levelset::Backend::Gpu}));
  }
}

// ISOATLAS_GL_PROFILE=1 prints the GPU extraction's stages to stderr and changes nothing else: the
// mesh is the one made without it, vertex for vertex.
TEST(MarchingCubesGpu, ProfileNamesItsStagesAndLeavesTheMeshAlone) {
  test::glContext();
  const Volume torus = test::fieldVolume({30, 28, 16}, [](double x, double y, double z) {
    const double q = std::hypot(x - 14.6, y - 13.3) - 8;
    return 4 - std::sqrt(q * q + (z - 7.6) * (z - 7.6));
  });
  const ExtractOptions gpu{.iso = 0.0f, .backend = levelset::Backend::Gpu};
  struct Restore {  // the variable as it was, whatever happens below
    std::optional<std::string> was;
    ~Restore() {
      if (was) setenv("ISOATLAS_GL_PROFILE", was->c_str(), 1);
      else unsetenv("ISOATLAS_GL_PROFILE");
    }
  } restore{std::getenv("ISOATLAS_GL_PROFILE") ? std::optional<std::string>(std::getenv("ISOATLAS_GL_PROFILE")) : std::nullopt};

  unsetenv("ISOATLAS_GL_PROFILE");
  ::testing::internal::CaptureStderr();
  const Mesh plain = extractSurface(torus, gpu);
  const std::string quiet = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(quiet.find("isoatlas gl profile"), std::string::npos) << quiet;

  setenv("ISOATLAS_GL_PROFILE", "1", 1);
  ::testing::internal::CaptureStderr();
  const Mesh profiled = extractSurface(torus, gpu);
  const std::string log = ::testing::internal::GetCapturedStderr();
  for (const char* stage : {"choose blocks (cpu)", "programs", "upload phi", "upload tables, size and clear buffers",
                            "classify cells", "count edges", "scan cell triangles", "scan cell centres",
                            "scan edge vertices", "emit vertices", "emit triangles", "read back mesh",
                            "assemble mesh (cpu)", "total"})
    EXPECT_NE(log.find(std::string("isoatlas gl profile: extract gpu: marching cubes: ") + stage + ": "), std::string::npos)
        << stage << " missing from:\n" << log;
  // A march for the mesh only has no drawn vertices, so no box to read back.
  EXPECT_EQ(log.find("read back the box"), std::string::npos) << log;
  for (const char* stage : {"marching cubes", "keep components (cpu)", "to world, smooth (cpu)", "total"})
    EXPECT_NE(log.find(std::string("isoatlas gl profile: extract gpu: ") + stage + ": "), std::string::npos)
        << stage << " missing from:\n" << log;
  // The inner lines first (marching cubes ends before the outer call does), one line per stage.
  EXPECT_LT(log.find("marching cubes: classify cells"), log.find("extract gpu: keep components"));
  std::size_t lines = 0;
  for (std::size_t at = log.find("marching cubes: classify cells: "); at != std::string::npos;
       at = log.find("marching cubes: classify cells: ", at + 1))
    ++lines;
  EXPECT_EQ(lines, 1u);

  ASSERT_GT(plain.faceCount(), 0u);
  EXPECT_TRUE(plain.positions == profiled.positions);
  EXPECT_TRUE(plain.faceVertices == profiled.faceVertices);
  EXPECT_TRUE(plain.faceOffsets == profiled.faceOffsets);
}

// Skipped blocks cut the surface open; both paths must still agree on which vertices exist (an edge
// has one when any of the four cells around it is visited) and on every triangle.
TEST(MarchingCubesGpu, GivesTheCpuMeshWhenBlocksAreSkipped) {
  test::glContext();
  const Volume torus = test::fieldVolume({37, 30, 21}, [](double x, double y, double z) {
    const double q = std::hypot(x - 17.6, y - 14.3) - 10;
    return 5 - std::sqrt(q * q + (z - 10.4) * (z - 10.4));
  });
  const Grid grid{torus.dims, reinterpret_cast<const float*>(torus.data.data())};
  // Blocks visited at random, so that every way of visiting some of the four cells around an edge
  // occurs (a pattern like a checkerboard never visits one cell of four alone).
  std::mt19937 rng(6);  // a draw under which dropping any one of the four cells from the rule fails
  const std::int64_t nx = blockCount(37, 8), ny = blockCount(30, 8), nz = blockCount(21, 8);
  const MarchingResult all = marchingCubesCpu(grid, 0.0f, 8, [](std::int64_t, std::int64_t, std::int64_t) { return true; });
  // Two in five blocks; then one in eight, so that whole rows of blocks go unvisited beside visited
  // ones (the CPU reads only the rows of points its visited cells touch).
  for (const unsigned inEight : {3u, 1u}) {
    std::vector<char> visit(std::size_t(nx * ny * nz));
    for (char& v : visit) v = rng() % 8 < inEight;
    auto scattered = [&](std::int64_t bx, std::int64_t by, std::int64_t bz) { return visit[std::size_t((bz * ny + by) * nx + bx)] != 0; };
    const MarchingResult cpu = marchingCubes(levelset::Backend::Cpu, grid, 0.0f, 8, scattered);
    ASSERT_GT(cpu.mesh.faceCount(), all.mesh.faceCount() / 20);
    ASSERT_LT(cpu.mesh.faceCount(), all.mesh.faceCount() * 4 / 5);
    const MarchingResult gpu = marchingCubes(levelset::Backend::Gpu, grid, 0.0f, 8, scattered);
    expectSameMesh(cpu.mesh, gpu.mesh);
    EXPECT_EQ(cpu.cellsVisited, gpu.cellsVisited);
    EXPECT_LT(cpu.cellsVisited, all.cellsVisited);
  }
  // A random field has surface in most cells, so every way rows of visited and unvisited blocks
  // can meet is met: e.g. a row of blocks visited whose three neighbours above it in y and z are not.
  std::uniform_real_distribution<float> value(-1, 1);
  const Volume noise = test::fieldVolume({33, 33, 33}, [&](double, double, double) { return value(rng); });
  const Grid noiseGrid{noise.dims, reinterpret_cast<const float*>(noise.data.data())};
  for (int draw = 0; draw < 4; ++draw) {
    std::vector<char> visit(5 * 5 * 5);
    for (char& v : visit) v = rng() % 6 == 0;
    auto sparse = [&](std::int64_t bx, std::int64_t by, std::int64_t bz) { return visit[std::size_t((bz * 5 + by) * 5 + bx)] != 0; };
    expectSameMesh(marchingCubes(levelset::Backend::Cpu, noiseGrid, 0.0f, 8, sparse).mesh,
                   marchingCubes(levelset::Backend::Gpu, noiseGrid, 0.0f, 8, sparse).mesh);
  }
}

TEST(ExtractLevelSet, ActivePagesGiveTheSameSurfaceForLessWork) {
  Volume image = test::fieldVolume({128, 128, 40}, [](double x, double y, double z) {
    return std::sqrt((x - 40) * (x - 40) + (y - 40) * (y - 40) + (z - 20) * (z - 20)) < 10 ? 100.0 : 20.0;
  });
  levelset::LevelSet ls(image, {100, 40, 0.8f});
  ls.addSphere({40, 40, 20}, 3);
  ls.run({.maxIterations = 400});
  ExtractStats paged, dense;
  const Mesh a = extractLevelSet(ls, {}, &paged);
  const Mesh b = extractSurface(ls.phi(), {.iso = 0.0f}, &dense);
  expectClosedManifold(a, 0);
  EXPECT_EQ(a.faceCount(), b.faceCount());
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_LT(paged.cellsVisited, paged.cellsTotal / 10) << "the cost follows the surface";
  // A phi that is not the level set's own (other dimensions, or not float) is refused.
  EXPECT_THROW(extractLevelSet(ls, Volume::zeros({64, 128, 40}, ScalarType::Float32), {}), Error);
  EXPECT_THROW(extractLevelSet(ls, ls.mask(), {}), Error);
}

// A phantom cut by the volume's edge: a bright slab-like blob that crosses the +x face (where 45 is
// no multiple of the page size, so edge pages are cut) and the -z face, segmented on `backend`.
std::unique_ptr<levelset::LevelSet> edgePhantomLevelSet(levelset::Backend backend, int pageSize, int iterations) {
  const Volume image = test::fieldVolume({45, 38, 17}, [](double x, double y, double z) {
    const double r = std::sqrt((x - 34) * (x - 34) / 2 + (y - 18) * (y - 18) + (z - 2) * (z - 2));
    return r < 11 ? 100.0 : 20.0;
  });
  auto ls = std::make_unique<levelset::LevelSet>(image, levelset::SpeedParams{100, 40, 0.8f},
                                                 levelset::LevelSetOptions{.backend = backend, .pageSize = pageSize, .initialSlots = 64});
  ls->addSphere({34, 18, 3}, 3);
  ls->run({.maxIterations = iterations, .untilConverged = false});
  return ls;
}

// Extraction from the pages gives the mesh the dense phi gives, on both backends, on both paths,
// while the front still moves (iterations 12) and once it has stopped at the volume's edges (200).
TEST(ExtractLevelSet, PagesGiveTheDensePhisMeshOnBothBackends) {
  test::glContext();
  for (const auto backend : {levelset::Backend::Cpu, levelset::Backend::Gpu})
    for (const int iterations : {12, 200})
      for (const int pageSize : {8, 16}) {
        SCOPED_TRACE(std::string(backend == levelset::Backend::Cpu ? "cpu" : "gpu") + " level set, " +
                     std::to_string(iterations) + " iterations, pages of " + std::to_string(pageSize));
        const auto ls = edgePhantomLevelSet(backend, pageSize, iterations);
        const Volume phi = ls->phi();
        // The dense phi over every block: the whole truth, with no page in sight.
        const Mesh truth = extractSurface(phi, {.iso = 0.0f});
        ASSERT_GT(truth.faceCount(), 100u);
        expectClosedManifold(truth, 0);
        ExtractStats cpuPages, gpuPages, gpuDense;
        const Mesh onCpu = extractLevelSet(*ls, {}, &cpuPages);
        EXPECT_EQ(cpuPages.path, "cpu pages");
        expectIdenticalMesh(onCpu, truth);
        const Mesh onGpu = extractLevelSet(*ls, {.backend = levelset::Backend::Gpu}, &gpuPages);
        EXPECT_EQ(gpuPages.path, backend == levelset::Backend::Gpu ? "gpu pages" : "cpu pages");
        expectSameMesh(onGpu, truth);
        if (backend == levelset::Backend::Gpu) {
          const Mesh dense = extractLevelSet(*ls, phi, {.backend = levelset::Backend::Gpu}, &gpuDense);
          expectIdenticalMesh(onGpu, dense);
        }
      }
}

// GPU memory follows the surface, not the grid: the same ball in a volume 16 times larger (padded
// with background on the +x and +y sides, whole pages and blocks) gives the same mesh for nearly the
// same memory from the pages (the page and block tables grow, 4 bytes a page and a block), where
// the dense path's grows with the volume.
TEST(ExtractLevelSet, GpuMemoryFollowsTheSurfaceNotTheGrid) {
  test::glContext();
  ExtractStats pages[2], dense[2];
  Mesh meshes[2];
  std::size_t voxels[2];
  for (int big = 0; big < 2; ++big) {
    const std::int64_t side = big ? 192 : 48;
    const Volume image = test::fieldVolume({side, side, 24}, [](double x, double y, double z) {
      return std::sqrt((x - 20) * (x - 20) + (y - 22) * (y - 22) + (z - 12) * (z - 12)) < 9 ? 100.0 : 20.0;
    });
    levelset::LevelSet ls(image, {100, 40, 0.8f}, {.backend = levelset::Backend::Gpu});
    ls.addSphere({20, 22, 12}, 3);
    ls.run({.maxIterations = 150});
    meshes[big] = extractLevelSet(ls, {.backend = levelset::Backend::Gpu}, &pages[big]);
    extractLevelSet(ls, ls.phi(), {.backend = levelset::Backend::Gpu}, &dense[big]);
    voxels[big] = image.voxelCount();
  }
  expectIdenticalMesh(meshes[0], meshes[1]);
  const double grownVoxels = double(voxels[1] - voxels[0]);
  EXPECT_GT(double(dense[1].gpuBytes) - double(dense[0].gpuBytes), 4 * grownVoxels) << "a dense phi's growth at least";
  EXPECT_LT(double(pages[1].gpuBytes) - double(pages[0].gpuBytes), 0.05 * grownVoxels)
      << "from the pages: only the tables grow (" << pages[0].gpuBytes << " -> " << pages[1].gpuBytes << " bytes)";
}

// The CPU marching cubes' mesh does not depend on the thread count (1, 2 or 8 threads).
TEST(MarchingCubes, TheCpuMeshIsTheSameOnOneTwoOrEightThreads) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> value(-1, 1);
  const Volume v = test::fieldVolume({40, 33, 29}, [&](double, double, double) { return value(rng); });
  auto extract = [&] { return extractSurface(v, {.iso = 0.0f}); };
  EXPECT_EQ(test::onThreads(8, [] { return tbb::this_task_arena::max_concurrency(); }), 8) << "8 threads even on 2 cores";
  const Mesh one = test::onThreads(1, extract);
  for (const int threads : {2, 8}) {
    const Mesh m = test::onThreads(threads, extract);
    EXPECT_TRUE(m.positions == one.positions) << threads << " threads";
    EXPECT_TRUE(m.faceVertices == one.faceVertices) << threads << " threads";
  }
}

}  // namespace
}  // namespace isoatlas::extract
