// bench/extract: isoatlas's marching cubes
//   openvdb: beside OpenVDB's volumeToMesh on the same field: the white-matter level set of
//            data/volumes/ch2better.nii.gz (301 x 370 x 316, 0.5 mm), segmented once by isoatlas's CPU
//            solver and kept in data/derived/. Seconds (median of 7) and triangles (an OpenVDB quad
//            counts as two). OpenVDB gets the same field as its own narrow-band level set, built outside
//            the timing. With ISOATLAS_BENCH_GPU set, the GPU path beside the CPU path too.
//   pages:   extraction straight from the level set's pages beside extraction of the dense phi (read
//            back whole first, as a user of phi() pays it), on ch2's white matter after segmentation
//            with the demo's seeds: seconds (median of 5), host heap peak (MiB, counted by this
//            program's operator new) and GPU memory the extraction allocates (MiB). CPU backend; with
//            ISOATLAS_BENCH_GPU set, the GPU backend too.
// Usage: bench_extract DATA [openvdb|pages] (both when no name is given).
#include <malloc.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "bench/bench_util.h"
#include "bench/derived_data.h"
#include "core/gl/context.h"
#include "core/volume_io.h"
#include "extract/extract_surface.h"
#include "pipeline/demo.h"
#include "levelset/level_set.h"

// Host heap in use and its peak, counted by every operator new of this program.
namespace {
std::atomic<std::int64_t> g_heap{0}, g_heapPeak{0};
void* counted(std::size_t n) {
  void* p = std::malloc(n ? n : 1);
  if (!p) throw std::bad_alloc();
  const std::int64_t now = g_heap += std::int64_t(malloc_usable_size(p));
  for (std::int64_t peak = g_heapPeak; now > peak && !g_heapPeak.compare_exchange_weak(peak, now);) {
  }
  return p;
}
void uncounted(void* p) {
  if (!p) return;
  g_heap -= std::int64_t(malloc_usable_size(p));
  std::free(p);
}
}  // namespace
void* operator new(std::size_t n) { return counted(n); }
void* operator new[](std::size_t n) { return counted(n); }
void operator delete(void* p) noexcept { uncounted(p); }
void operator delete[](void* p) noexcept { uncounted(p); }
void operator delete(void* p, std::size_t) noexcept { uncounted(p); }
void operator delete[](void* p, std::size_t) noexcept { uncounted(p); }

using namespace isoatlas;

namespace {

constexpr double kMiB = 1024.0 * 1024.0;

// The extra host heap `work` reaches at its peak, in MiB, above what was in use before it.
double heapPeakMiB(const std::function<void()>& work) {
  const std::int64_t before = g_heap;
  g_heapPeak = before;
  work();
  return double(g_heapPeak - before) / kMiB;
}

// The GPU's name for the table.
std::string deviceName(const gl::Context& context) { return context.info().renderer + ", " + bench::machineName(); }

// gpu: the process's GL context, when the GPU path is measured too (ISOATLAS_BENCH_GPU).
void openVdbComparison(const std::string& data, const gl::Context* gpu) {
  const Volume phi = bench::ch2betterWhiteMatterPhi(data);

  std::size_t ours = 0;
  const double oursSeconds = bench::medianSeconds(7, [&] {
    ours = extract::extractSurface(phi, {.iso = 0.0f}).faceCount();
  });

  openvdb::initialize();
  // OpenVDB's own level-set form: negative inside, the narrow band active, the rest inactive tiles
  // of +-background after a signed flood fill. (A dense copy keeps the whole inside active, and
  // volumeToMesh then meshes ten times too many quads.)
  const auto& d = phi.dims;
  const float* p = reinterpret_cast<const float*>(phi.data.data());
  auto grid = openvdb::FloatGrid::create(levelset::kClamp);
  {
    auto accessor = grid->getAccessor();
    for (std::int64_t z = 0; z < d[2]; ++z)
      for (std::int64_t y = 0; y < d[1]; ++y)
        for (std::int64_t x = 0; x < d[0]; ++x) {
          const float v = p[std::size_t((z * d[1] + y) * d[0] + x)];
          if (std::fabs(v) < levelset::kClamp) accessor.setValue(openvdb::Coord(int(x), int(y), int(z)), -v);
        }
  }
  openvdb::tools::signedFloodFill(grid->tree());
  std::size_t theirs = 0;
  const double theirSeconds = bench::medianSeconds(7, [&] {
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(*grid, points, triangles, quads, 0.0);
    theirs = triangles.size() + 2 * quads.size();
  });
  const std::string name = "ch2better white matter (" + std::to_string(d[0]) + "x" + std::to_string(d[1]) + "x" +
                            std::to_string(d[2]) + ")";
  bench::report("extract", name + ", isoatlas cpu", "seconds", oursSeconds, "OpenVDB 10 volumeToMesh", theirSeconds);
  bench::report("extract", name + ", isoatlas cpu", "triangles", double(ours), "OpenVDB 10 volumeToMesh",
                double(theirs), false);

  // The GPU path beside the CPU path (issue 4: at least 10x on a real GPU), when asked: on llvmpipe
  // the figure says nothing. In the process's one context, its programs compiled by an untimed first
  // call, as in a session that extracts more than once.
  if (gpu) {
    const std::string device = deviceName(*gpu);
    extract::extractSurface(phi, {.iso = 0.0f, .backend = levelset::Backend::Gpu});
    std::size_t gpuTriangles = 0;
    const double gpuSeconds = bench::medianSeconds(7, [&] {
      gpuTriangles = extract::extractSurface(phi, {.iso = 0.0f, .backend = levelset::Backend::Gpu}).faceCount();
    });
    bench::report("extract", name + ", isoatlas gpu", "seconds", gpuSeconds, "isoatlas cpu path (TBB)", oursSeconds,
                  true, device);
    bench::report("extract", name + ", isoatlas gpu", "triangles", double(gpuTriangles), "isoatlas cpu path (TBB)",
                  double(ours), false, device);
  }
}

// Pages against the dense phi on one backend's level set of ch2's white matter; returns the seconds
// from the pages. On the GPU, also the surface left there (buffers kept from the call before, nothing
// read back but its box: the window's live surface) against the CPU's from the pages (cpuSeconds).
double pagesAgainstDense(const Volume& ch2, levelset::Backend backend, const std::string& device, double cpuSeconds = 0) {
  const bool gpu = backend == levelset::Backend::Gpu;
  levelset::LevelSet ls(ch2, pipeline::kDemoParams, {.backend = backend});
  for (const Vec3& seed : pipeline::kDemoSeeds) ls.addSphere(seed, pipeline::kDemoSeedRadius);
  const levelset::RunStats run = ls.run({.maxIterations = 3000});
  std::fprintf(stderr, "bench: ch2 white matter segmented on the %s in %d iterations (%s), %zu active pages\n",
               gpu ? "GPU" : "CPU", run.iterations, run.converged ? "converged" : "not converged",
               ls.pages().activePages().size());
  const extract::ExtractOptions options{.backend = backend};
  extract::ExtractStats pagesStats, denseStats;
  std::size_t pagesTriangles = 0, denseTriangles = 0;
  auto fromPages = [&] { pagesTriangles = extract::extractLevelSet(ls, options, &pagesStats).faceCount(); };
  auto fromDense = [&] { denseTriangles = extract::extractLevelSet(ls, ls.phi(), options, &denseStats).faceCount(); };
  fromPages();  // compiles the GPU's programs, untimed
  fromDense();
  const double pagesSeconds = bench::medianSeconds(5, fromPages), denseSeconds = bench::medianSeconds(5, fromDense);
  const double pagesHeap = heapPeakMiB(fromPages), denseHeap = heapPeakMiB(fromDense);
  const std::string name = std::string("ch2 white matter (181x217x181), ") + (gpu ? "gpu" : "cpu") + " from the pages";
  const std::string peer = std::string("isoatlas ") + (gpu ? "gpu" : "cpu") + " from the dense phi (read back first)";
  bench::report("extract", name, "seconds", pagesSeconds, peer, denseSeconds, true, device);
  bench::report("extract", name, "host heap peak MiB", pagesHeap, peer, denseHeap, true, device);
  if (gpu)
    bench::report("extract", name, "GPU MiB allocated", double(pagesStats.gpuBytes) / kMiB, peer,
                  double(denseStats.gpuBytes) / kMiB, true, device);
  bench::report("extract", name, "triangles", double(pagesTriangles), peer, double(denseTriangles), false, device);
  if (gpu) {
    extract::GpuMarchingCubes kept;
    std::uint32_t keptTriangles = 0;
    auto onGpu = [&] { keptTriangles = extract::marchLevelSetOnGpu(ls, kept).triangleCount; };
    onGpu();  // the buffers grown once, untimed
    const double keptSeconds = bench::medianSeconds(7, onGpu);
    const std::string keptName = "ch2 white matter (181x217x181), gpu from the pages, left on the GPU (buffers kept)";
    bench::report("extract", keptName, "seconds", keptSeconds, "isoatlas cpu from the pages (TBB)", cpuSeconds, true, device);
    bench::report("extract", keptName, "triangles", double(keptTriangles), "isoatlas gpu from the pages, read back",
                  double(pagesTriangles), false, device);
  }
  return pagesSeconds;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string data = argc > 1 ? argv[1] : "data";
  const std::string only = argc > 2 ? argv[2] : "";
  // One context for the process, made before any GPU object and destroyed after them all.
  const auto gpu = std::getenv("ISOATLAS_BENCH_GPU") ? gl::Context::headless() : nullptr;
  if (only.empty() || only == "openvdb") openVdbComparison(data, gpu.get());
  if (only.empty() || only == "pages") {
    const Volume ch2 = readVolume(data + "/volumes/ch2.nii.gz");
    const double cpuSeconds = pagesAgainstDense(ch2, levelset::Backend::Cpu, "");
    if (gpu) pagesAgainstDense(ch2, levelset::Backend::Gpu, deviceName(*gpu), cpuSeconds);
  }
  return 0;
}
