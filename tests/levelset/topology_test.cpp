// The topology-preserving level set (--topology preserve) against truth: the simple-point test on
// configurations whose answer is known; random flips of the points it calls simple leave the marching
// cubes surface's components and Euler characteristic as they were (the connectivity the two share);
// a ball in the torus phantom stops as a sphere where the free solver makes a torus; two seeds stay
// two components; the GPU gives its CPU twin's mask voxel for voxel; a mask's topology figures on
// known shapes; the half-resolution start keeps the seeds' topology, or is left out where halving
// would change it.
#include <gtest/gtest.h>

#include <functional>
#include <random>

#include "core/mesh_topology.h"
#include "extract/marching_cubes.h"
#include "levelset/fill_threads.h"
#include "levelset/level_set.h"
#include "levelset/simple_point.h"
#include "pipeline/mask_topology.h"
#include "pipeline/segmentation.h"
#include "tests/gl_context.h"
#include "tests/levelset/phantom.h"

namespace isoatlas::levelset {
namespace {

constexpr std::uint32_t bit(int dx, int dy, int dz) { return neighbourBit(dx, dy, dz); }
constexpr std::uint32_t kAll = (1u << 27) - 1;

TEST(SimplePoint, KnownConfigurations) {
  EXPECT_FALSE(isSimplePoint(0)) << "alone: adding it makes a component, removing it ends one";
  EXPECT_FALSE(isSimplePoint(kAll)) << "inside: removing it makes a cavity";
  EXPECT_TRUE(isSimplePoint(bit(1, 0, 0))) << "the end of a line";
  EXPECT_TRUE(isSimplePoint(kAll & ~bit(1, 0, 0))) << "on a flat face";
  EXPECT_FALSE(isSimplePoint(bit(1, 0, 0) | bit(-1, 0, 0))) << "within a line: removing it cuts it";
  EXPECT_FALSE(isSimplePoint(bit(1, 1, 0))) << "only an edge neighbour: the object is 6-connected";
  EXPECT_FALSE(isSimplePoint(bit(1, 1, 1))) << "only a corner neighbour";
  EXPECT_FALSE(isSimplePoint(kAll & ~bit(1, 1, 1))) << "all but a corner: the background is 18-connected, so the corner is a cavity";
  EXPECT_TRUE(isSimplePoint(kAll & ~bit(1, 1, 0))) << "all but an edge neighbour: it joins the background across x";
  std::uint32_t lower = 0, ring = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      lower |= bit(dx, dy, -1);
      if (dx || dy) ring |= bit(dx, dy, 0);
    }
  EXPECT_TRUE(isSimplePoint(lower)) << "above a flat layer";
  EXPECT_FALSE(isSimplePoint(ring)) << "the hole of a ring: filling it removes a tunnel";
  EXPECT_FALSE(isSimplePoint(kAll & ~ring)) << "the centre of a ring of background: a tunnel through the object";
  // Two face neighbours joined through an edge neighbour, or only through the ring of corners and
  // edges past a third: the geodesic neighbourhood counts the first as one, the second as two.
  EXPECT_TRUE(isSimplePoint(bit(1, 0, 0) | bit(0, 1, 0) | bit(1, 1, 0)));
  EXPECT_FALSE(isSimplePoint(bit(1, 0, 0) | bit(0, 1, 0)));
}

// A field of +1 inside and -1 outside on a grid.
struct SignGrid {
  std::array<std::int64_t, 3> dims;
  std::vector<float> v;
  float& at(std::int64_t x, std::int64_t y, std::int64_t z) { return v[std::size_t((z * dims[1] + y) * dims[0] + x)]; }
  std::uint32_t insideAround(std::int64_t x, std::int64_t y, std::int64_t z) {
    return insideBits([&](int dx, int dy, int dz) {
      const std::int64_t a = x + dx, b = y + dy, c = z + dz;
      return a >= 0 && b >= 0 && c >= 0 && a < dims[0] && b < dims[1] && c < dims[2] && at(a, b, c) > 0;
    });
  }
  MeshTopology surface() const {
    return analyzeTopology(extract::marchingCubes(Backend::Cpu, {dims, v.data()}, 0.0f).mesh);
  }
};

// Random flips of the points isSimplePoint calls simple, on blobs with handles and cavities: the
// surface marching cubes traces keeps its components and Euler characteristic at every check, though
// most of the object changes. (Made to call every point simple, the test fails at its first check.)
TEST(SimplePoint, FlippingSimplePointsKeepsTheMarchingCubesSurfacesTopology) {
  SignGrid g{{20, 18, 16}, {}};
  g.v.assign(std::size_t(20 * 18 * 16), -1.0f);
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> xs(1, 18), ys(1, 16), zs(1, 14);
  for (int k = 0; k < 700; ++k) g.at(xs(rng), ys(rng), zs(rng)) = 1.0f;  // salt: many components, handles, cavities
  const MeshTopology before = g.surface();
  ASSERT_GT(before.components, 20u);
  int flips = 0;
  for (int check = 0; check < 20; ++check) {
    for (int tries = 0; tries < 4000; ++tries) {
      const std::int64_t x = xs(rng), y = ys(rng), z = zs(rng);
      if (!isSimplePoint(g.insideAround(x, y, z))) continue;
      g.at(x, y, z) = -g.at(x, y, z);
      ++flips;
    }
    const MeshTopology now = g.surface();
    ASSERT_TRUE(now.closed) << "check " << check;
    ASSERT_EQ(now.components, before.components) << "after " << flips << " flips";
    ASSERT_EQ(now.euler, before.euler) << "after " << flips << " flips";
  }
  EXPECT_GT(flips, 10000);
}

// A solid box with a line of background voxels from its centre: to the top face only (a cavity's
// thread), or through to the bottom face too (a tunnel).
Volume boxWithLine(bool through) {
  Volume m = Volume::zeros({14, 14, 14}, ScalarType::UInt8);
  for (std::int64_t z = 2; z < 12; ++z)
    for (std::int64_t y = 2; y < 12; ++y)
      for (std::int64_t x = 2; x < 12; ++x) m.setValue(m.index(x, y, z), 1);
  for (std::int64_t z = through ? 2 : 7; z < 12; ++z) m.setValue(m.index(7, 7, z), 0);
  return m;
}
MeshTopology maskSurface(const Volume& mask) {
  const std::vector<float> f = mask.toFloat();
  return analyzeTopology(extract::marchingCubes(Backend::Cpu, {mask.dims, f.data()}, 0.5f).mesh);
}

// The thread is filled to the surface (the box's last voxel of it is a dent of one); the tunnel, whose
// every voxel is needed to keep it, is left; the topology is each one's before.
TEST(FillThreads, FillsACavitysThreadAndLeavesATunnel) {
  Volume thread = boxWithLine(false);
  const MeshTopology before = maskSurface(thread);
  EXPECT_EQ(fillThreads(thread), 4);  // z = 7 .. 10 of 7 .. 11
  const MeshTopology after = maskSurface(thread);
  EXPECT_EQ(after.components, before.components);
  EXPECT_EQ(after.genus, 0);
  EXPECT_EQ(thread.at(7, 7, 7), 1);
  Volume tunnel = boxWithLine(true);
  EXPECT_EQ(maskSurface(tunnel).genus, 1);
  EXPECT_EQ(fillThreads(tunnel), 0);
  EXPECT_EQ(maskSurface(tunnel).genus, 1);
}

Volume segment(const Phantom& p, Backend backend, Topology topology, bool twoSeeds) {
  LevelSet ls(p.image, {100, 30, 0.7f}, {.backend = backend, .topology = topology});
  ls.addSphere(p.seedA, 3);
  if (twoSeeds) ls.addSphere(p.seedB, 3);
  ls.run({.maxIterations = 600});
  return ls.phi();
}
MeshTopology surfaceOf(const Volume& phi) {
  return analyzeTopology(extract::marchingCubes(Backend::Cpu, {phi.dims, reinterpret_cast<const float*>(phi.data.data())}, 0.0f).mesh);
}

// The free solver fills the torus (genus 1 and more); preserving the topology, the ball grows round it
// until its two ends meet and stops there as a sphere, with nearly the same voxels.
TEST(TopologyPreservingLevelSet, ABallInTheTorusStopsAsASphere) {
  const Phantom p = torusPhantom();
  const Volume free = segment(p, Backend::Cpu, Topology::Free, false);
  const Volume kept = segment(p, Backend::Cpu, Topology::Preserve, false);
  const MeshTopology f = surfaceOf(free), k = surfaceOf(kept);
  // The free front also leaves cavities round the noise's outliers (about a hundred), and a handle or two.
  EXPECT_GT(f.components, 1u);
  EXPECT_GE(f.genus, 1);
  EXPECT_EQ(k.components, 1u);
  EXPECT_EQ(k.genus, 0);
  EXPECT_TRUE(k.closed);
  EXPECT_GE(dice(maskOf(kept), p.truth), 0.95);
  EXPECT_GE(dice(maskOf(kept), maskOf(free)), 0.97);
}

// Two seeds: the fronts meet twice and stay two spheres.
TEST(TopologyPreservingLevelSet, TwoSeedsStayTwoComponents) {
  const Phantom p = torusPhantom();
  const MeshTopology free = surfaceOf(segment(p, Backend::Cpu, Topology::Free, true));
  const Volume kept = segment(p, Backend::Cpu, Topology::Preserve, true);
  const MeshTopology k = surfaceOf(kept);
  EXPECT_GE(free.genus, 1);
  EXPECT_EQ(k.components, 2u);
  EXPECT_EQ(k.genus, 0);
  EXPECT_GE(dice(maskOf(kept), p.truth), 0.95);
}

// maskTopology on shapes of known topology: a ball, a hollow ball, two balls, a solid torus.
TEST(MaskTopology, CountsComponentsCavitiesAndHandles) {
  const auto shape = [](const std::function<bool(double, double, double)>& inside) {
    Volume m = Volume::zeros({40, 40, 30}, ScalarType::UInt8);
    for (std::int64_t z = 0; z < 30; ++z)
      for (std::int64_t y = 0; y < 40; ++y)
        for (std::int64_t x = 0; x < 40; ++x) m.setValue(m.index(x, y, z), inside(double(x) - 20, double(y) - 20, double(z) - 15));
    return m;
  };
  const auto r = [](double x, double y, double z) { return std::sqrt(x * x + y * y + z * z); };
  using pipeline::MaskTopology, pipeline::maskTopology;
  EXPECT_EQ(maskTopology(shape([&](double x, double y, double z) { return r(x, y, z) < 8; })), (MaskTopology{1, 1, 2}));
  EXPECT_EQ(maskTopology(shape([&](double x, double y, double z) { return r(x, y, z) < 10 && r(x, y, z) > 5; })), (MaskTopology{1, 2, 4}));
  EXPECT_EQ(maskTopology(shape([&](double x, double y, double z) { return r(x - 9, y, z) < 6 || r(x + 9, y, z) < 6; })),
            (MaskTopology{2, 2, 4}));
  EXPECT_EQ(maskTopology(shape([&](double x, double y, double z) { return std::pow(std::hypot(x, y) - 11, 2) + z * z < 16; })),
            (MaskTopology{1, 1, 0}));
}

// --half-resolution-start with the topology preserved: the half-resolution solve keeps it too, so the
// ball in the ring still stops as a sphere, as the full start's does, with nearly its voxels.
TEST(HalfResolutionStart, KeepsTheSeedsTopologyWhenPreserved) {
  const Phantom p = torusPhantom();
  pipeline::SegmentationRequest request{.params = {100, 30, 0.7f}, .seeds = {{p.seedA, 3}}, .maxIterations = 600,
                                        .untilConverged = true, .topology = Topology::Preserve};
  const pipeline::Segmentation full = pipeline::segmentVolume(p.image, request);
  request.halfResolutionStart = true;
  const pipeline::Segmentation half = pipeline::segmentVolume(p.image, request);
  EXPECT_TRUE(half.halfResolutionStarted);
  EXPECT_GT(half.halfResolution.iterations, 0);
  EXPECT_EQ(pipeline::maskTopology(half.mask), (pipeline::MaskTopology{1, 1, 2})) << "a sphere, as the full start's";
  EXPECT_EQ(pipeline::maskTopology(full.mask), (pipeline::MaskTopology{1, 1, 2}));
  EXPECT_GE(dice(half.mask, full.mask), 0.97);
  // Free, the half-resolution start closes the ring as the full start does.
  request.topology = Topology::Free;
  EXPECT_LE(pipeline::maskTopology(pipeline::segmentVolume(p.image, request).mask).euler, 0);
}

// Two seeds a voxel apart are two components; halved, they touch: the start from half resolution
// would make them one, so it is left out and the segmentation is the full start's, voxel for voxel.
TEST(HalfResolutionStart, SeedsThatHalvingJoinsStartAtFullResolution) {
  const Phantom p = torusPhantom();
  pipeline::SegmentationRequest request{.params = {100, 30, 0.7f},
                                        .seeds = {{p.seedA - Vec3{1, 0, 0}, 1.2}, {p.seedA + Vec3{3, 0, 0}, 1.2}},
                                        .maxIterations = 600, .untilConverged = true, .topology = Topology::Preserve};
  const pipeline::Segmentation full = pipeline::segmentVolume(p.image, request);
  request.halfResolutionStart = true;
  const pipeline::Segmentation half = pipeline::segmentVolume(p.image, request);
  EXPECT_FALSE(half.halfResolutionStarted);
  EXPECT_EQ(half.halfResolution.iterations, 0);
  EXPECT_EQ(pipeline::maskTopology(full.mask).components, 2);
  EXPECT_TRUE(half.mask.data == full.mask.data);
}

// The GPU's eight parity passes give the CPU twin's decisions: the same mask, voxel for voxel.
TEST(TopologyPreservingLevelSet, GpuGivesTheCpuMask) {
  test::glContext();
  const Phantom p = torusPhantom();
  const Volume cpu = maskOf(segment(p, Backend::Cpu, Topology::Preserve, true));
  const Volume gpu = maskOf(segment(p, Backend::Gpu, Topology::Preserve, true));
  std::int64_t differ = 0;
  for (std::size_t n = 0; n < cpu.voxelCount(); ++n) differ += cpu.data[n] != gpu.data[n];
  EXPECT_EQ(differ, 0);
  EXPECT_EQ(surfaceOf(segment(p, Backend::Gpu, Topology::Preserve, false)).genus, 0);
}

}  // namespace
}  // namespace isoatlas::levelset
