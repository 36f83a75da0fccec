// The paged level-set solver against truth: analytic curvature flow and propagation of a sphere, a
// noisy phantom with known truth (Dice), the page invariants (no gradient outside active pages,
// pages released and reused, the pool growing without changing the answer), steering, and the GPU
// against its CPU twin; the CPU solver's row stencil against the per-voxel update bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <utility>

#include "core/error.h"
#include "core/mapped_nifti.h"
#include "core/volume_io.h"
#include "levelset/cpu_solver.h"
#include "levelset/level_set.h"
#include "levelset/probe.h"
#include "levelset/row_stencil.h"
#include "pipeline/coarse_start.h"
#include "pipeline/segmentation.h"
#include "tests/gl_context.h"
#include "tests/levelset/phantom.h"
#include "tests/test_util.h"
#include "tests/thread_count.h"

namespace isoatlas::levelset {
namespace {

Volume uniformVolume(std::array<std::int64_t, 3> dims, float value) {
  Volume v = Volume::zeros(dims, ScalarType::Float32);
  for (std::size_t n = 0; n < v.voxelCount(); ++n) v.setValue(n, value);
  return v;
}

double largestDifference(const Volume& a, const Volume& b) {
  double worst = 0;
  for (std::size_t i = 0; i < a.voxelCount(); ++i) worst = std::max(worst, std::abs(a.value(i) - b.value(i)));
  return worst;
}

// Sub-voxel volume of the model: phi is a distance near the front, so clamp(phi + 1/2, 0, 1) is the
// fraction of each voxel inside.
double modelVolume(const LevelSet& ls) {
  const Volume phi = ls.phi();
  double sum = 0;
  for (std::size_t n = 0; n < phi.voxelCount(); ++n) sum += std::clamp(phi.value(n) + 0.5, 0.0, 1.0);
  return sum;
}
double equivalentRadius(const LevelSet& ls) { return std::cbrt(3 * modelVolume(ls) / (4 * M_PI)); }

// Every voxel of an inactive page equals its six neighbours (outside the volume counts as -kClamp).
std::int64_t gradientOutsideActivePages(const LevelSet& ls) {
  const Volume phi = ls.phi();
  const PageManager& pm = ls.pages();
  const int P = pm.pageSize();
  std::int64_t bad = 0;
  for (std::int64_t z = 0; z < phi.dims[2]; ++z)
    for (std::int64_t y = 0; y < phi.dims[1]; ++y)
      for (std::int64_t x = 0; x < phi.dims[0]; ++x) {
        if (pm.isActive(pm.pageIndex(x / P, y / P, z))) continue;
        const double c = phi.at(x, y, z);
        const std::int64_t n[6][3] = {{x + 1, y, z}, {x - 1, y, z}, {x, y + 1, z}, {x, y - 1, z}, {x, y, z + 1}, {x, y, z - 1}};
        for (const auto& q : n) {
          const bool in = q[0] >= 0 && q[1] >= 0 && q[2] >= 0 && q[0] < phi.dims[0] && q[1] < phi.dims[1] && q[2] < phi.dims[2];
          if ((in ? phi.at(q[0], q[1], q[2]) : -kClamp) != c) ++bad;
        }
      }
  return bad;
}

// The row stencil shares each face normal between the two voxels of the face; every value must
// still be evaluateVoxelAt's to the bit, on aprons with a band, clamped plateaus and ties, for runs
// of rows starting and ending anywhere, and for rows cut short by the volume's edge.
TEST(RowStencil, RowsGiveEvaluateVoxelAtBitForBit) {
  std::mt19937 rng(7);
  const SpeedParams params{112, 14, 0.8f};
  for (const int P : {16, 8}) {
    const int side = P + 2;
    std::vector<float> apron(std::size_t(3 * side * side));
    std::uniform_real_distribution<float> value(-4, 4), intensityOf(80, 140);
    for (float& v : apron) {
      const float u = value(rng);
      v = std::clamp(std::round(u * 4) / 4 * (u > 0 ? 1.3f : 1.0f), -kClamp, kClamp);  // plateaus at the clamp, ties
    }
    std::vector<float> intensity(std::size_t(P * P));
    for (float& i : intensity) i = intensityOf(rng);
    auto at = [&](int x, int y, int dz) { return apron[std::size_t(((dz + 1) * side + y + 1) * side + x + 1)]; };
    for (const auto& [y0, y1, xEnd] : {std::array<int, 3>{0, P, P}, {3, 7, P}, {P - 1, P, P}, {0, P, P - 3}}) {
      std::vector<float> faces(std::size_t(kMaxPageSize * (kMaxPageSize + 1))), speed(std::size_t(kMaxPageSize * P)),
          rate(std::size_t(kMaxPageSize * P));
      std::vector<std::uint32_t> moving(std::size_t(P), 0u);
      rowFaceNormals(apron.data(), side, y0 - 1, y1, xEnd, faces.data());
      evaluateRows(apron.data(), side, y0, y1, xEnd, intensity.data() + std::size_t(y0 * P), std::size_t(P), params,
                   faces.data(), std::size_t(kMaxPageSize), speed.data(), rate.data(), moving.data());
      for (int y = y0; y < y1; ++y)
        for (int x = 0; x < xEnd; ++x) {
          const VoxelUpdate want = evaluateVoxelAt([&](int dx, int dy, int dz) { return at(x + dx, y + dy, dz); },
                                                   intensity[std::size_t(y * P + x)], params);
          const std::size_t k = std::size_t(y - y0) * kMaxPageSize + std::size_t(x);
          ASSERT_EQ(std::bit_cast<std::uint32_t>(speed[k]), std::bit_cast<std::uint32_t>(want.speed)) << P << " " << x << " " << y;
          ASSERT_EQ(std::bit_cast<std::uint32_t>(rate[k]), std::bit_cast<std::uint32_t>(want.rate)) << P << " " << x << " " << y;
          ASSERT_EQ((moving[std::size_t(y - y0)] >> x) & 1u, want.rate != 0 ? 1u : 0u) << P << " " << x << " " << y;
        }
    }
  }
}

TEST(PageManager, ActivateReleaseReuseAndNeighbours) {
  PageManager pm({40, 33, 5}, 16, 8);
  EXPECT_EQ(pm.pages(), (std::array<std::int64_t, 3>{3, 3, 5}));
  const std::int64_t a = pm.pageIndex(1, 1, 2), b = pm.pageIndex(2, 1, 2);
  const std::int32_t sa = pm.activate(a);
  EXPECT_GT(sa, kInsideSlot);
  EXPECT_EQ(pm.pageOfSlot(sa), a);
  const std::int32_t sb = pm.activate(b);
  auto n = pm.neighbourSlots(a);
  EXPECT_EQ(n[13], sa);
  EXPECT_EQ(n[14], sb);                      // +x
  EXPECT_EQ(n[12], kOutsideSlot);            // -x, inactive
  pm.release(a, true);
  EXPECT_EQ(pm.slotOf(a), kInsideSlot);
  EXPECT_EQ(pm.pageOfSlot(sa), -1);
  EXPECT_EQ(pm.activate(pm.pageIndex(0, 0, 0)), sa) << "the freed slot is reused first";
  EXPECT_EQ(pm.neighbourSlots(pm.pageIndex(0, 0, 0))[0], kOutsideSlot) << "outside the volume reads outside";
  // More active pages than the pool holds: it grows by whole rows, and slot origins stay put.
  PageManager big({200, 200, 10}, 4, 8);
  const std::int32_t before = big.capacity();
  const auto firstOrigin = big.slotOrigin(big.activate(0));
  for (std::int64_t p = 1; p < big.virtualPageCount(); ++p) big.activate(p);
  EXPECT_GT(big.capacity(), before);
  EXPECT_GT(big.stats().growths, 0);
  EXPECT_EQ(big.stats().active, big.virtualPageCount());
  EXPECT_EQ(big.slotOrigin(big.slotOf(0)), firstOrigin);
  // The CPU's contiguous pool: slot s's P x P texels are texels s P^2 to (s + 1) P^2 - 1, x fastest,
  // also after the pool has grown.
  PageManager contiguous({200, 200, 10}, 4, 8, PoolLayout::Contiguous);
  for (std::int64_t p = 0; p < contiguous.virtualPageCount(); ++p) contiguous.activate(p);
  EXPECT_EQ(contiguous.poolPagesX(), 1);
  const std::int64_t last = contiguous.virtualPageCount() - 1;
  const auto [lx, ly, lz] = contiguous.pageCoords(last);
  EXPECT_EQ(contiguous.poolTexel(lx * 4 + 3, ly * 4 + 2, lz), std::size_t(contiguous.slotOf(last)) * 16 + 2 * 4 + 3);
  EXPECT_GE(contiguous.capacity(), contiguous.virtualPageCount() + 2);
}

TEST(PageManager, RenumberingGivesTheActivePagesSlotsInPageOrder) {
  PageManager pm({64, 64, 6}, 16, 8, PoolLayout::Contiguous);
  const std::vector<std::int64_t> pages = {pm.pageIndex(3, 2, 5), pm.pageIndex(0, 1, 0), pm.pageIndex(2, 2, 2),
                                           pm.pageIndex(1, 0, 4), pm.pageIndex(0, 0, 1)};
  for (const std::int64_t page : pages) pm.activate(page);
  pm.release(pages[2], true);  // a hole in the slots, and the list reordered by swap-remove
  std::map<std::int64_t, std::int32_t> slotBefore;
  for (const std::int64_t page : pm.activePages()) slotBefore[page] = pm.slotOf(page);
  const auto moves = pm.renumberInPageOrder();
  const std::vector<std::int64_t> sorted = {pages[1], pages[4], pages[3], pages[0]};  // by page index
  ASSERT_EQ(pm.activePages(), sorted);
  for (std::size_t k = 0; k < sorted.size(); ++k) {
    const std::int32_t slot = kInsideSlot + 1 + std::int32_t(k);
    EXPECT_EQ(pm.slotOf(sorted[k]), slot);
    EXPECT_EQ(pm.pageOfSlot(slot), sorted[k]);
    // Every page whose slot changed has a move from its old slot to its new one, and only those.
    const bool moved = std::find(moves.begin(), moves.end(), std::pair{slotBefore[sorted[k]], slot}) != moves.end();
    EXPECT_EQ(moved, slotBefore[sorted[k]] != slot) << k;
  }
  EXPECT_EQ(moves.size(), std::size_t(std::count_if(sorted.begin(), sorted.end(), [&](std::int64_t p) { return slotBefore[p] != pm.slotOf(p); })));
  EXPECT_EQ(pm.slotOf(pages[2]), kInsideSlot) << "a released page stays static";
  EXPECT_EQ(pm.pageOfSlot(kInsideSlot + 5), -1) << "the slot past the active ones is free";
  EXPECT_EQ(pm.changesSinceRenumbering(), 0);
  EXPECT_EQ(pm.activate(pm.pageIndex(1, 1, 1)), kInsideSlot + 5) << "the next activation takes the first free slot";
  pm.release(sorted[0], false);
  EXPECT_EQ(pm.changesSinceRenumbering(), 2);
  EXPECT_EQ(pm.activate(pm.pageIndex(2, 1, 1)), kInsideSlot + 1) << "a freed slot is reused first";
  // A page released and activated again takes its slot back but joins the end of the list: renumbering
  // moves no value then, yet sorts the list.
  pm.renumberInPageOrder();
  const std::vector<std::int64_t> inOrder = pm.activePages();
  pm.release(inOrder[1], false);
  pm.activate(inOrder[1]);
  ASSERT_NE(pm.activePages(), inOrder);
  EXPECT_TRUE(pm.renumberInPageOrder().empty());
  EXPECT_EQ(pm.activePages(), inOrder);
  for (std::int64_t page = 0; page < pm.virtualPageCount(); ++page) pm.activate(page);  // the free slots run out: the pool grows
  EXPECT_EQ(pm.stats().active, pm.virtualPageCount());
  std::set<std::int32_t> slots;
  for (const std::int64_t page : pm.activePages()) slots.insert(pm.slotOf(page));
  EXPECT_EQ(slots.size(), std::size_t(pm.virtualPageCount())) << "no slot handed out twice";
  EXPECT_GT(*slots.begin(), kInsideSlot);
}

TEST(LevelSet, CurvatureFlowShrinksASphereAsTheAnalyticLaw) {
  // alpha = 0: dR/dt = H = -1/R, so R(t)^2 = R0^2 - 2t.
  LevelSet ls(uniformVolume({48, 48, 48}, 0), {0, 1, 0});
  const double r0 = 12;
  ls.addSphere({24, 23.5, 24.25}, r0);
  const double start = equivalentRadius(ls);
  EXPECT_NEAR(start, r0, 0.2);
  while (ls.simulatedTime() < 30) ls.step();
  const double expected = std::sqrt(start * start - 2 * ls.simulatedTime());
  // The shrink itself (about 2.8 voxels) is what the law predicts, to 5 % (the scheme gives 3.8 % more);
  // a bound on the radius alone would let a sixth of it be wrong.
  const double shrink = start - equivalentRadius(ls), expectedShrink = start - expected;
  EXPECT_NEAR(shrink, expectedShrink, 0.05 * expectedShrink) << "t = " << ls.simulatedTime();
}

TEST(LevelSet, PropagationMovesTheFrontAtTheSpeedOfD) {
  // alpha = 1 and I = T everywhere: D = eps, so R(t) = R0 + eps t. At eps = 0.5 the time step is set
  // by G_r's bound; at 2 and 20 by the CFL condition, the front moving close to half a voxel per step.
  for (const float eps : {0.5f, 2.0f, 20.0f}) {
    LevelSet ls(uniformVolume({48, 48, 48}, 10), {10, eps, 1});
    ls.addSphere({24, 24, 24}, 6);
    const double start = equivalentRadius(ls);
    while (ls.simulatedTime() < 7 / eps) ls.step();
    const double expected = start + eps * ls.simulatedTime();
    // The thesis's scheme sums every speed before choosing the upwind gradient, and G_r steepens the
    // band's outer side: the front runs a few percent slow on a sphere. 5 % bounds it.
    EXPECT_NEAR(equivalentRadius(ls), expected, 0.05 * expected) << "eps " << eps;
    EXPECT_EQ(gradientOutsideActivePages(ls), 0) << "eps " << eps;
  }
}

TEST(LevelSet, NoisyTorusPhantomIsSegmentedWithDiceAbove95) {
  const Phantom p = torusPhantom();
  LevelSet ls(p.image, {100, 30, 0.7f});
  ls.addSphere(p.seedA, 3);
  ls.addSphere(p.seedB, 3);
  const RunStats stats = ls.run({.maxIterations = 600});
  EXPECT_TRUE(stats.converged) << stats.iterations << " iterations";
  EXPECT_GE(dice(ls.mask(), p.truth), 0.95);
  EXPECT_EQ(gradientOutsideActivePages(ls), 0);
}

// The half-resolution start (pipeline/coarse_start.h): each half voxel is its block's mean (fewer
// voxels at an odd edge), and lies where its block does.
TEST(HalfResolutionStart, HalfVoxelsAreTheirBlocksMeansWhereTheBlocksAre) {
  Volume v = Volume::zeros({5, 4, 3}, ScalarType::Float32);
  v.spacing = {0.5, 1, 2};
  v.origin = {1, -2, 3};
  for (std::size_t n = 0; n < v.voxelCount(); ++n) v.setValue(n, double(n * n % 17));
  const Volume h = pipeline::halfResolution(v);
  ASSERT_EQ(h.dims, (std::array<std::int64_t, 3>{3, 2, 2}));
  for (std::int64_t z = 0; z < 2; ++z)
    for (std::int64_t y = 0; y < 2; ++y)
      for (std::int64_t x = 0; x < 3; ++x) {
        double sum = 0;
        int n = 0;
        for (std::int64_t Z = 2 * z; Z < std::min<std::int64_t>(2 * z + 2, 3); ++Z)
          for (std::int64_t Y = 2 * y; Y < 2 * y + 2; ++Y)
            for (std::int64_t X = 2 * x; X < std::min<std::int64_t>(2 * x + 2, 5); ++X, ++n) sum += v.at(X, Y, Z);
        EXPECT_NEAR(h.at(x, y, z), sum / n, 1e-5) << x << " " << y << " " << z;
        const Vec3 a = h.indexToWorld({double(x), double(y), double(z)});
        const Vec3 b = v.indexToWorld({2.0 * x + 0.5, 2.0 * y + 0.5, 2.0 * z + 0.5});
        EXPECT_NEAR(norm(a - b), 0, 1e-9);
      }
}

// Started from its solution at half the resolution, the noisy torus settles in fewer full-resolution
// steps on the segmentation the seeds give (from spheres or from a seed mask alike).
TEST(HalfResolutionStart, TheTorusFromHalfResolutionIsTheTorusFromTheSeedsInFewerSteps) {
  const Phantom p = torusPhantom();
  const SpeedParams params{100, 30, 0.7f};
  LevelSet full(p.image, params);
  full.addSphere(p.seedA, 3);
  full.addSphere(p.seedB, 3);
  const RunStats fullStats = full.run({.maxIterations = 600});
  ASSERT_TRUE(fullStats.converged);
  Volume seedMask = p.image.sameGeometry(ScalarType::UInt8);
  for (std::int64_t z = 0; z < seedMask.dims[2]; ++z)
    for (std::int64_t y = 0; y < seedMask.dims[1]; ++y)
      for (std::int64_t x = 0; x < seedMask.dims[0]; ++x) {
        const Vec3 q{double(x), double(y), double(z)};
        seedMask.setValue(seedMask.index(x, y, z), norm(q - p.seedA) < 3 || norm(q - p.seedB) < 3);
      }
  for (const bool fromMask : {false, true}) {
    SCOPED_TRACE(fromMask ? "seed mask" : "seed spheres");
    const std::vector<pipeline::Ball> seeds = fromMask ? std::vector<pipeline::Ball>{}
                                                       : std::vector<pipeline::Ball>{{p.seedA, 3}, {p.seedB, 3}};
    const pipeline::CoarseStart start =
        pipeline::solveAtHalfResolution(p.image, params, seeds, fromMask ? &seedMask : nullptr, {}, {.maxIterations = 600});
    EXPECT_TRUE(start.stats.converged);
    ASSERT_EQ(start.mask.dims, p.image.dims);
    EXPECT_GE(dice(start.mask, p.truth), 0.93) << "the half-resolution solution, in place on the volume's grid";
    LevelSet fine(p.image, params);
    fine.setMask(start.mask);
    const RunStats stats = fine.run({.maxIterations = 600});
    EXPECT_TRUE(stats.converged);
    EXPECT_LT(stats.iterations, fullStats.iterations);
    EXPECT_GE(dice(fine.mask(), full.mask()), 0.99);
    EXPECT_GE(dice(fine.mask(), p.truth), 0.95);
    EXPECT_EQ(gradientOutsideActivePages(fine), 0);
  }
}

// The rule by hand: ten voxels for a small band, one in 20,000 of a large one, whichever is more;
// the share switched off leaves the ten.
TEST(LevelSet, ConvergenceCountsAShareOfTheActiveVoxels) {
  const RunOptions defaults;
  EXPECT_TRUE(windowConverged(9, 1000, defaults));
  EXPECT_FALSE(windowConverged(10, 1000, defaults));
  EXPECT_TRUE(windowConverged(99, 2'000'000, defaults));
  EXPECT_FALSE(windowConverged(100, 2'000'000, defaults));
  EXPECT_FALSE(windowConverged(99, 2'000'000, {.changedShare = 0}));
}

TEST(LevelSet, PagesAreReleasedBehindTheFrontAndReused) {
  // Small pages, so the growing sphere leaves whole pages of plateau behind it.
  LevelSet ls(uniformVolume({48, 48, 48}, 10), {10, 0.5f, 1}, {.pageSize = 4});
  ls.addSphere({24, 24, 24}, 5);
  for (int i = 0; i < 40; ++i) {
    ls.step();
    ASSERT_EQ(gradientOutsideActivePages(ls), 0) << "after step " << i;
  }
  const auto& stats = ls.pages().stats();
  EXPECT_GT(stats.releases, 0);
  EXPECT_LT(stats.peakActive, stats.activations) << "freed slots were taken again";
  EXPECT_EQ(ls.pages().staticSlot(ls.pages().pageIndex(6, 6, 24)), kInsideSlot) << "the centre page went static inside";
  // The CPU backend's memory counts the pool of phi, the per-page tables and the active pages'
  // intensities (TheSolversReadTheSourcePageByPage below).
  const std::uint64_t pool = std::uint64_t(ls.pages().capacity()) * 4 * 4 * sizeof(float);
  EXPECT_GE(ls.physicalBytes(), pool);
}

// A volume segmented from its file read in place (an uncompressed NIfTI, mapped) gives the mask of
// the same volume read into memory, on both backends, from the seeds and from the half resolution
// (read from the source two rows at a time).
TEST(LevelSet, AFileReadInPlaceSegmentsAsTheVolumeInMemory) {
  test::glContext();
  const Phantom p = torusPhantom();
  const std::string path = (test::scratchDir() / "torus.nii").string();
  writeVolume(path, p.image);
  bool mapped = false;
  const std::shared_ptr<const VolumeSource> source = openVolumeSource(path, {}, &mapped);
  ASSERT_TRUE(mapped);
  const Volume read = readVolume(path);
  for (const Backend backend : {Backend::Cpu, Backend::Gpu})
    for (const bool half : {false, true}) {
      SCOPED_TRACE(std::string(backend == Backend::Cpu ? "cpu" : "gpu") + (half ? ", half-resolution start" : ""));
      const pipeline::SegmentationRequest request{.params = {100, 30, 0.7f}, .seeds = {{p.seedA, 3}}, .backend = backend,
                                                  .maxIterations = 300, .untilConverged = true, .halfResolutionStart = half};
      const pipeline::Segmentation inPlace = pipeline::segmentVolume(source, request), inMemory = pipeline::segmentVolume(read, request);
      EXPECT_EQ(inPlace.halfResolutionStarted, half);
      EXPECT_EQ(inPlace.stats.iterations, inMemory.stats.iterations);
      EXPECT_GT(inPlace.insideVoxels, 1000);
      EXPECT_EQ(inPlace.mask.data, inMemory.mask.data);
    }
}

// A source that counts the rows read from it.
class CountingSource final : public VolumeSource {
public:
  explicit CountingSource(Volume v) : VolumeSource(v), inner_(std::move(v)) {}
  void readRow(std::int64_t x0, std::int64_t y, std::int64_t z, std::int64_t n, float* out) const override {
    ++rows;
    inner_.readRow(x0, y, z, n, out);
  }
  bool wholeBytes() const override { return inner_.wholeBytes(); }
  std::uint64_t heldBytes() const override { return inner_.heldBytes(); }
  mutable std::atomic<std::int64_t> rows{0};

private:
  VolumeInMemory inner_;
};

// One value everywhere, made as it is read: a source that holds nothing.
class UniformSource final : public VolumeSource {
public:
  UniformSource(std::array<std::int64_t, 3> dims, float value) : VolumeSource(geometryOf(dims)), value_(value) {}
  void readRow(std::int64_t, std::int64_t, std::int64_t, std::int64_t n, float* out) const override { std::fill_n(out, n, value_); }
  bool wholeBytes() const override { return false; }
  std::uint64_t heldBytes() const override { return 0; }

private:
  static Volume geometryOf(std::array<std::int64_t, 3> dims) {
    Volume v;
    v.dims = dims;
    return v;
  }
  float value_;
};

// The solvers read the source page by page as pages become active (P rows each), and (the CPU's)
// hold only the active pages' intensities besides what the source holds.
TEST(LevelSet, TheSolversReadTheSourcePageByPage) {
  test::glContext();
  const Phantom p = torusPhantom();
  // Intensities off whole numbers, so the CPU keeps floats (4 bytes a voxel, were it the volume).
  Volume fractional = p.image.sameGeometry(ScalarType::Float32);
  for (std::size_t n = 0; n < p.image.voxelCount(); ++n) fractional.setValue(n, p.image.value(n) + 0.25);
  for (const Backend backend : {Backend::Cpu, Backend::Gpu}) {
    SCOPED_TRACE(backend == Backend::Cpu ? "cpu" : "gpu");
    const LevelSetOptions options{.backend = backend, .pageSize = 8, .initialSlots = 16, .pagesOnDevice = false};
    auto source = std::make_shared<CountingSource>(fractional);
    LevelSet paged(source, {100, 30, 0.7f}, options);
    paged.addSphere(p.seedA, 3);
    paged.run({.maxIterations = 60, .untilConverged = false});
    // Each page read once a time it became active (8 rows, fewer at the volume's edge), none other.
    const std::int64_t activations = paged.pages().stats().activations;
    EXPECT_GT(activations, 0);
    EXPECT_LE(source->rows.load(), 8 * activations);
    EXPECT_GT(source->rows.load(), 4 * activations);
  }
  // A small band in a large volume (16 MB of floats, which the CPU solver held whole before): from a
  // source that holds nothing, the solver's memory is the band's; from a Volume, its copy counts too.
  const std::array<std::int64_t, 3> dims{256, 256, 64};
  const std::uint64_t volumeFloats = std::uint64_t(256 * 256 * 64) * sizeof(float);
  const LevelSetOptions cpu{.pageSize = 16, .initialSlots = 64};
  LevelSet small(std::make_shared<UniformSource>(dims, 10.25f), {10, 0.5f, 1}, cpu), copied(uniformVolume(dims, 10.25f), {10, 0.5f, 1}, cpu);
  for (LevelSet* ls : {&small, &copied}) {
    ls->addSphere({128, 128, 32}, 4);
    for (int i = 0; i < 5; ++i) ls->step();
  }
  const std::uint64_t activeFloats = std::uint64_t(small.pages().activePages().size()) * 16 * 16 * sizeof(float);
  EXPECT_LT(small.physicalBytes(), volumeFloats / 8) << "the band's pages, not the volume";
  EXPECT_GE(small.physicalBytes(), 2 * activeFloats) << "phi and the intensities of every active page";
  EXPECT_GE(copied.physicalBytes(), volumeFloats) << "the level set's copy of a Volume, as floats";
  EXPECT_EQ(largestDifference(small.phi(), copied.phi()), 0.0);
}

// On both backends: growing keeps every slot's content (phi and, on the GPU, the source's pages).
TEST(LevelSet, PoolGrowsWhenItMustAndTheAnswerDoesNotChange) {
  test::glContext();
  const Phantom p = torusPhantom();
  for (const Backend backend : {Backend::Cpu, Backend::Gpu}) {
    auto segment = [&](std::int32_t slots) {
      LevelSet ls(p.image, {100, 30, 0.7f}, {.backend = backend, .pageSize = 4, .initialSlots = slots});
      ls.addSphere(p.seedA, 3);
      for (int i = 0; i < 100; ++i) ls.step();
      return std::pair{ls.phi(), ls.pages().stats().growths};
    };
    const auto [small, growths] = segment(1024);
    const auto [large, none] = segment(1 << 16);
    const char* name = backend == Backend::Cpu ? "cpu" : "gpu";
    EXPECT_GT(growths, 0) << name;
    EXPECT_EQ(none, 0) << name;
    ASSERT_EQ(small.data.size(), large.data.size());
    EXPECT_TRUE(small.data == large.data) << name << ": the same phi, bit for bit";
  }
}

TEST(LevelSet, SteeringSpheresAndParameters) {
  const Phantom p = torusPhantom();
  LevelSet ls(p.image, {100, 30, 0.7f});
  ls.addSphere(p.seedA, 3);
  ls.run({.maxIterations = 600});
  const Vec3 cut = p.seedA;
  ASSERT_EQ(ls.mask().at(std::int64_t(cut.x), std::int64_t(cut.y), std::int64_t(cut.z)), 1);
  ls.addSphere(cut, 5, false);  // model off
  const Volume cutMask = ls.mask();
  EXPECT_EQ(cutMask.at(std::int64_t(cut.x), std::int64_t(cut.y), std::int64_t(cut.z)), 0);
  EXPECT_EQ(cutMask.at(std::int64_t(cut.x) + 4, std::int64_t(cut.y), std::int64_t(cut.z)), 0);
  // A target no voxel matches: the model shrinks away.
  ls.setParams({1000, 5, 1});
  ls.run({.maxIterations = 300});
  std::int64_t inside = 0;
  const Volume gone = ls.mask();
  for (std::size_t n = 0; n < gone.voxelCount(); ++n) inside += gone.value(n) > 0;
  EXPECT_EQ(inside, 0);
  EXPECT_THROW(ls.setParams({100, 0, 0.5}), Error);
  EXPECT_THROW(ls.setParams({100, 5, 1.5}), Error);
}

// Settled pages (LevelSetOptions::settledChange): skipping the pages whose phi and whose neighbours'
// phi no longer move leaves the segmentation as it was.
TEST(LevelSet, SettledPagesLeaveTheSegmentationAsItWas) {
  const Phantom p = torusPhantom();
  auto segment = [&](float settledChange) {
    LevelSet ls(p.image, {100, 30, 0.7f}, {.settledChange = settledChange});
    ls.addSphere(p.seedA, 3);
    ls.addSphere(p.seedB, 3);
    EXPECT_TRUE(ls.run({.maxIterations = 600}).converged);
    return ls.mask();
  };
  EXPECT_GE(dice(segment(kSettledChange), segment(0)), 0.999);
}

// Once the front has stopped, every page settles and an iteration changes nothing; a new speed
// wakes them all: the front, stopped at a bright ball's edge, grows to the dimmer shell around it.
TEST(LevelSet, ANewSpeedWakesSettledPages) {
  const std::array<std::int64_t, 3> dims{48, 48, 48};
  Volume image = Volume::zeros(dims, ScalarType::Float32);
  for (std::int64_t z = 0; z < dims[2]; ++z)
    for (std::int64_t y = 0; y < dims[1]; ++y)
      for (std::int64_t x = 0; x < dims[0]; ++x) {
        const double r = std::hypot(double(x) - 24, double(y) - 24, double(z) - 24);
        image.setValue(image.index(x, y, z), r < 8 ? 100 : r < 16 ? 70 : 20);
      }
  LevelSet ls(image, {100, 20, 1});  // D > 0 in the bright ball only
  ls.addSphere({24, 24, 24}, 3);
  ls.run({.maxIterations = 400});
  for (int i = 0; i < 200; ++i) ls.step();
  const Volume settled = ls.phi();
  ls.step();
  ASSERT_TRUE(ls.phi().data == settled.data) << "a step after the front stopped still changed phi";
  EXPECT_NEAR(equivalentRadius(ls), 8, 1);
  ls.setParams({85, 25, 1});  // D > 0 in the shell too
  ls.run({.maxIterations = 400});
  EXPECT_NEAR(equivalentRadius(ls), 16, 1);
}

TEST(LevelSet, StartsFromAMaskTouchingTheBorder) {
  const Phantom p = torusPhantom();
  Volume seed = p.truth;  // start at the truth itself, plus a block at the volume's corner
  for (std::int64_t z = 0; z < 4; ++z)
    for (std::int64_t y = 0; y < 4; ++y)
      for (std::int64_t x = 0; x < 4; ++x) seed.setValue(seed.index(x, y, z), 1);
  LevelSet ls(p.image, {100, 30, 0.7f});
  ls.setMask(seed);
  EXPECT_DOUBLE_EQ(dice(ls.mask(), seed), 1.0);
  ls.run({.maxIterations = 400});
  EXPECT_GE(dice(ls.mask(), p.truth), 0.95);
  EXPECT_EQ(gradientOutsideActivePages(ls), 0);
}

TEST(LevelSet, GpuAgreesWithCpu) {
  test::glContext();
  const Phantom p = torusPhantom();
  auto segment = [&](Backend b) {
    LevelSet ls(p.image, {100, 30, 0.7f}, {.backend = b});
    ls.addSphere(p.seedA, 3);
    ls.addSphere(p.seedB, 3);
    const RunStats stats = ls.run({.maxIterations = 600});
    if (b == Backend::Gpu) {
      EXPECT_GT(stats.bytesReadBackPerIteration, 0u);
    }
    return ls.mask();
  };
  const Volume cpu = segment(Backend::Cpu);
  const Volume gpu = segment(Backend::Gpu);
  EXPECT_GE(dice(cpu, gpu), 0.99);
  EXPECT_GE(dice(gpu, p.truth), 0.95);
}

// Step by step, not only where both converge: the same time steps and nearly the same phi.
TEST(LevelSet, GpuStepsLikeCpu) {
  test::glContext();
  const Phantom p = torusPhantom();
  LevelSet cpu(p.image, {100, 30, 0.7f}, {.backend = Backend::Cpu});
  LevelSet gpu(p.image, {100, 30, 0.7f}, {.backend = Backend::Gpu});
  for (LevelSet* ls : {&cpu, &gpu}) ls->addSphere(p.seedA, 3);
  for (int i = 0; i < 30; ++i) {
    cpu.step();
    gpu.step();
    ASSERT_NEAR(gpu.simulatedTime(), cpu.simulatedTime(), 1e-4 * cpu.simulatedTime()) << "step " << i;
  }
  EXPECT_LT(largestDifference(cpu.phi(), gpu.phi()), 1e-3);
  // The mask made page by page is the dense phi's.
  for (const LevelSet* ls : {&cpu, &gpu}) EXPECT_TRUE(ls->mask().data == maskOf(ls->phi()).data);
}

// The GPU keeps the source's intensities in pages beside phi's: a slot released by one page and
// taken by another must hold the new page's intensities, and pages cut off by the volume's edge
// must hold its intensities where it has them. Small pages on a phantom 58 voxels wide (its torus
// reaches the +x edge, in pages half outside); a model-off sphere frees pages, new fronts take the
// slots; CPU and GPU must still step alike.
TEST(LevelSet, GpuSourcePagesFollowReusedSlots) {
  test::glContext();
  const Phantom p = torusPhantom(58);
  auto options = [](Backend b) { return LevelSetOptions{.backend = b, .pageSize = 4}; };
  LevelSet cpu(p.image, {100, 30, 0.7f}, options(Backend::Cpu));
  LevelSet gpu(p.image, {100, 30, 0.7f}, options(Backend::Gpu));
  for (LevelSet* ls : {&cpu, &gpu}) ls->addSphere(p.seedA, 4);
  for (int i = 0; i < 20; ++i) cpu.step(), gpu.step();
  const PageManager& pages = gpu.pages();
  bool edge = false;
  for (std::int64_t page : pages.activePages()) edge |= pages.pageCoords(page)[0] == pages.pages()[0] - 1;
  EXPECT_TRUE(edge) << "no active page on the +x edge, which is cut off by the volume";
  std::vector<std::int64_t> owners(std::size_t(pages.capacity()));
  for (std::int32_t slot = 0; slot < pages.capacity(); ++slot) owners[std::size_t(slot)] = pages.pageOfSlot(slot);
  for (LevelSet* ls : {&cpu, &gpu}) ls->addSphere(p.seedA, 8, false), ls->addSphere(p.seedB, 4);
  for (int i = 0; i < 20; ++i) cpu.step(), gpu.step();
  int taken = 0;  // slots that held one page and now hold another (the pool may have grown since)
  for (std::int32_t slot = 0; slot < std::int32_t(owners.size()); ++slot) {
    const std::int64_t before = owners[std::size_t(slot)], now = pages.pageOfSlot(slot);
    taken += before >= 0 && now >= 0 && before != now;
  }
  EXPECT_GT(taken, 0);
  EXPECT_NEAR(gpu.simulatedTime(), cpu.simulatedTime(), 1e-4 * cpu.simulatedTime());
  EXPECT_LT(largestDifference(cpu.phi(), gpu.phi()), 1e-3);
}

// A ball past the volume's corner: out of the volume is outside, so the pages where the inside
// meets the volume's edge keep a band (are active), and both backends see the same edge.
TEST(LevelSet, BallPastTheCornerKeepsABandAtTheEdge) {
  test::glContext();
  const Volume image = uniformVolume({40, 40, 40}, 100);
  const Vec3 corner{39, 39, 20};
  LevelSet cpu(image, {100, 30, 0.7f}, {.backend = Backend::Cpu});
  LevelSet gpu(image, {100, 30, 0.7f}, {.backend = Backend::Gpu});
  for (LevelSet* ls : {&cpu, &gpu}) ls->addSphere(corner, 30);
  const PageManager& pages = cpu.pages();
  const int P = pages.pageSize();
  for (std::int64_t z = 0; z < 40; ++z) {
    const std::int64_t page = pages.pageIndex(39 / P, 39 / P, z);
    EXPECT_TRUE(pages.isActive(page)) << "z " << z;
  }
  for (int i = 0; i < 10; ++i) cpu.step(), gpu.step();
  EXPECT_LT(largestDifference(cpu.phi(), gpu.phi()), 1e-3);
}

// The GPU's page passes (gpu_page_chain.h) do the host's page work: the same phi bit for bit as the
// host applying each iteration's messages, the same pages active, the same iterations to
// convergence, on a pool that must grow on the GPU (small pages, 1024 slots), for a run whose length
// is not a multiple of the chain's, for both topologies (the preserving front converges after an
// odd number of iterations past the last full chain: which phi copy is current follows the
// iterations done) and with every page evaluated; and steps after the run, or a run the GPU
// declines, go on from the same state.
TEST(LevelSet, GpuPagesOnTheDeviceGiveTheHostDrivenPhiBitForBit) {
  test::glContext();
  const Phantom p = torusPhantom();
  struct Case {
    int pageSize;
    RunOptions run;
    Topology topology = Topology::Free;
    float settledChange = kSettledChange;
  };
  const Case cases[] = {{4, {.maxIterations = 600}},
                        {16, {.maxIterations = 37, .untilConverged = false}},
                        {8, {.maxIterations = 300}, Topology::Preserve},
                        {16, {.maxIterations = 100, .window = 7}, Topology::Free, 0.0f}};
  for (const Case& c : cases) {
    auto segment = [&](bool onDevice) {
      auto ls = std::make_unique<LevelSet>(p.image, SpeedParams{100, 30, 0.7f},
                                           LevelSetOptions{.backend = Backend::Gpu, .pageSize = c.pageSize, .settledChange = c.settledChange,
                                                           .topology = c.topology, .pagesOnDevice = onDevice});
      ls->addSphere(p.seedA, 3);
      ls->addSphere(p.seedB, 3);
      int progressed = 0;
      RunOptions run = c.run;
      run.progress = [&](int iteration, std::int64_t) { EXPECT_EQ(iteration, ++progressed); };
      const RunStats stats = ls->run(run);
      EXPECT_EQ(progressed, stats.iterations);
      return std::pair{std::move(ls), stats};
    };
    const auto [device, onDevice] = segment(true);
    const auto [host, hostDriven] = segment(false);
    const std::string name = "page size " + std::to_string(c.pageSize) + ", " + std::to_string(c.run.maxIterations) + " iterations";
    EXPECT_EQ(onDevice.iterations, hostDriven.iterations) << name;
    EXPECT_EQ(onDevice.converged, hostDriven.converged) << name;
    EXPECT_LT(onDevice.bytesReadBackPerIteration, hostDriven.bytesReadBackPerIteration) << name;
    EXPECT_EQ(device->simulatedTime(), host->simulatedTime()) << name;
    EXPECT_TRUE(device->phi().data == host->phi().data) << name << ": phi bit for bit";
    auto activeSet = [](const LevelSet& ls) {
      return std::set<std::int64_t>(ls.pages().activePages().begin(), ls.pages().activePages().end());
    };
    EXPECT_EQ(activeSet(*device), activeSet(*host)) << name;
    const auto &d = device->pages().stats(), &h = host->pages().stats();
    EXPECT_EQ(d.activations, h.activations) << name;
    EXPECT_EQ(d.releases, h.releases) << name;
    EXPECT_EQ(d.peakActive, h.peakActive) << name;
    EXPECT_EQ(d.growths, h.growths) << name;
    if (c.pageSize == 4) {
      EXPECT_GT(d.growths, 0) << name << ": the pool grew on the device";
    }
    for (int i = 0; i < 5; ++i) device->step(), host->step();
    EXPECT_TRUE(device->phi().data == host->phi().data) << name << ": steps after the run";
    // A run the GPU declines (a window past kChainRingSize) right after one it ran: the host goes on
    // from the pages the GPU found to evaluate.
    for (LevelSet* ls : {device.get(), host.get()}) {
      ls->run({.maxIterations = 7, .untilConverged = false});
      ls->run({.maxIterations = 9, .untilConverged = false, .window = kChainRingSize + 1});
    }
    EXPECT_TRUE(device->phi().data == host->phi().data) << name << ": a run the GPU declines";
  }
}

// Two GPU solvers in one context, used in turn and destroyed in either order: each keeps its own pool
// (the same steps give the same phi), and whichever goes first leaves the other working.
TEST(LevelSet, TwoGpuSolversShareOneContextAndDieInAnyOrder) {
  gl::Context& ctx = test::glContext();
  const Phantom p = torusPhantom(40);
  for (const bool firstDiesFirst : {true, false}) {
    auto first = std::make_unique<LevelSet>(p.image, SpeedParams{100, 30, 0.7f}, LevelSetOptions{.backend = Backend::Gpu});
    const int compiled = ctx.programsCompiled();  // the first solver's, made as it took its pages
    auto second = std::make_unique<LevelSet>(p.image, SpeedParams{100, 30, 0.7f}, LevelSetOptions{.backend = Backend::Gpu});
    LevelSet cpu(p.image, {100, 30, 0.7f});
    for (LevelSet* ls : {first.get(), second.get(), &cpu}) ls->addSphere(p.seedA, 3);
    for (int i = 0; i < 6; ++i) first->step(), second->step(), cpu.step();
    EXPECT_GT(compiled, 0);
    EXPECT_EQ(ctx.programsCompiled(), compiled) << "the second solver compiled its programs again";
    (firstDiesFirst ? first : second).reset();
    LevelSet& survivor = firstDiesFirst ? *second : *first;
    for (int i = 0; i < 6; ++i) survivor.step(), cpu.step();
    EXPECT_LT(largestDifference(cpu.phi(), survivor.phi()), 1e-3);
    gl::checkErrors("after the solvers");
  }
}

TEST(Probe, MeanAndSpreadOfAKnownBall) {
  const Phantom p = torusPhantom();
  const ProbeResult r = probeSphere(p.image, p.seedA, 4);
  EXPECT_NEAR(r.mean, 100, 3);
  EXPECT_NEAR(r.std, 12, 2);
  EXPECT_THROW(probeSphere(p.image, {-5, 0, 0}, 2), Error);
  EXPECT_THROW(probeSphere(p.image, {5, 5, 5}, 0), Error);
}

// The CPU solver's result does not depend on the thread count (1, 2 or 8 threads on any machine).
TEST(LevelSet, TheCpuSolverGivesTheSameLevelSetOnOneTwoOrEightThreads) {
  const Phantom p = torusPhantom();
  auto segment = [&] {
    LevelSet ls(p.image, {100, 30, 0.7f});
    ls.addSphere(p.seedA, 3);
    ls.addSphere(p.seedB, 3);
    ls.run({.maxIterations = 120});
    return ls.phi().data;
  };
  const auto one = test::onThreads(1, segment);
  EXPECT_TRUE(test::onThreads(2, segment) == one);
  EXPECT_TRUE(test::onThreads(8, segment) == one);
}

// The CPU solver keeps a source of whole numbers from 0 to 255 as bytes, any other as floats: the
// same intensities read either way give the same phi bit for bit (the torus rounded to whole numbers,
// and the same raised by 256 with the target raised alike, so |I - T| is the same in floats; 58
// voxels wide, so that the +x edge cuts pages).
TEST(LevelSet, TheCpuSolverReadsASourceOfBytesAsItsFloats) {
  const Phantom p = torusPhantom(58);
  Volume bytes = p.image, raised = p.image;
  for (std::size_t i = 0; i < std::size_t(p.image.voxelCount()); ++i) {
    const double v = std::clamp(std::round(p.image.value(i)), 0.0, 255.0);
    bytes.setValue(i, v);
    raised.setValue(i, v + 256);
  }
  auto segment = [&](const Volume& image, float target) {
    LevelSet ls(image, {target, 30, 0.7f});
    ls.addSphere(p.seedA, 3);
    ls.run({.maxIterations = 60});
    return ls.phi().data;
  };
  const auto fromBytes = segment(bytes, 100);
  EXPECT_TRUE(fromBytes == segment(raised, 356));
  EXPECT_FALSE(fromBytes == segment(raised, 357)) << "the comparison sees a change of target";
}

TEST(LevelSet, TheCpuSolverRefusesAnActiveListItWasNotToldOf) {
  // A page released and activated again joins the end of the list with its old slot; renumbering then
  // sorts the list back without moving a slot. A backend whose tables still follow the order before
  // would credit each page with another's results: it must refuse to iterate, not answer wrongly.
  PageManager pm({64, 16, 4}, 16, 8, PoolLayout::Contiguous);
  Volume ten = Volume::zeros({64, 16, 4}, ScalarType::Float32);
  for (std::size_t n = 0; n < ten.voxelCount(); ++n) ten.setValue(n, 10);
  const auto solver = makeCpuSolver(std::make_shared<VolumeInMemory>(ten), 16);
  for (std::int64_t x = 0; x < 3; ++x) pm.activate(pm.pageIndex(x, 0, 1));
  pm.renumberInPageOrder();  // slots 2, 3, 4 (the pages hold no values yet)
  solver->pagesChanged(pm, {});
  const std::vector<std::uint8_t> all(3, 1);
  const SpeedParams params{10, 30, 0.7f};
  EXPECT_NO_THROW(solver->iterate(pm, params, all, 0));
  const std::int64_t first = pm.activePages()[0];
  pm.release(first, false);
  pm.activate(first);
  solver->pagesChanged(pm, {});
  EXPECT_NO_THROW(solver->iterate(pm, params, all, 0));
  EXPECT_TRUE(pm.renumberInPageOrder().empty());
  EXPECT_THROW(solver->iterate(pm, params, all, 0), Error);
  solver->pagesChanged(pm, {});
  EXPECT_NO_THROW(solver->iterate(pm, params, all, 0));
}

TEST(LevelSet, RenumberingThePagesKeepsPhiBitForBit) {
  // The CPU backend renumbers its pages' slots as the band moves; phi must not see it.
  const Phantom p = torusPhantom(58);
  auto segment = [&](bool renumber, float target, std::int64_t* renumberings) {
    LevelSetOptions options;
    options.renumberPages = renumber;
    LevelSet ls(p.image, {target, 30, 0.7f}, options);
    ls.addSphere(p.seedA, 3);
    ls.run({.maxIterations = 1000});  // to convergence, where pages at the band's edge come and go
    *renumberings = ls.pages().stats().renumberings;
    return ls.phi().data;
  };
  std::int64_t renumbered = 0, notRenumbered = 0, other = 0;
  const auto withRenumbering = segment(true, 100, &renumbered);
  EXPECT_GT(renumbered, 1) << "the band grows through many pages: it must have been renumbered";
  EXPECT_TRUE(withRenumbering == segment(false, 100, &notRenumbered));
  EXPECT_EQ(notRenumbered, 0);
  EXPECT_FALSE(withRenumbering == segment(false, 101, &other)) << "the comparison sees a change of target";
}

}  // namespace
}  // namespace isoatlas::levelset
