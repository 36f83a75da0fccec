// bench/levelset: isoatlas's paged narrow-band solver beside ITK's sparse-field threshold level set,
// serial (ThresholdSegmentationLevelSetImageFilter) and parallel (ParallelSparseFieldLevelSetImageFilter
// driving ThresholdSegmentationLevelSetFunction, the solver ITK-SNAP's snake mode uses), same seeds,
// same speed: lower = T - eps, upper = T + eps, propagation = alpha, curvature = 1 - alpha, edge = 0.
// (ITK-SNAP's snake mode drives the same filter with a function of its own.)
// Convergence as issue 3 defines it: a solver has converged at N iterations when its mask at N and at
// 2N agree with Dice >= 0.999; its time to convergence is the wall time of those N iterations.
//   bench_levelset [DATA [CASE ...]]           every case (or the named ones) and solver, one process
//                                              each; JSON lines
//   bench_levelset --one SOLVER CASE DATA OUT  one solver on one case: writes OUT.nii.gz, prints JSON
//   bench_levelset --one-file SOLVER VOLUME "X,Y,Z,R;..." T EPS ALPHA OUT
//                                              one solver on any volume, seeds in voxels (the ITK
//                                              reference of tests/levelset/data: bench/itk-reference)
#include <itkImage.h>
#include <itkImportImageFilter.h>
#include <itkParallelSparseFieldLevelSetImageFilter.h>
#include <itkThresholdSegmentationLevelSetFunction.h>
#include <itkThresholdSegmentationLevelSetImageFilter.h>
#include <itkCommand.h>
#include <itkMultiThreaderBase.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "bench/bench_util.h"
#include "core/gl/context.h"
#include "core/volume_io.h"
#include "levelset/level_set.h"
#include "pipeline/coarse_start.h"

namespace {

using namespace isoatlas;
using Clock = std::chrono::steady_clock;
using Image = itk::Image<float, 3>;

struct Case {
  std::string name, file;
  std::vector<std::array<double, 4>> seeds;  // x, y, z, r (voxels)
  levelset::SpeedParams params;
  int maxIterations;
};

const std::vector<std::array<double, 4>> kSkullSeeds = {{30, 41, 10, 2}, {18, 38, 25, 2}, {43, 38, 25, 2}};

const std::vector<Case> kCases = {
    {"ch2 white matter", "volumes/ch2.nii.gz", {{64, 115, 101, 4}, {116, 115, 101, 4}}, {112, 14, 0.8f}, 8192},
    // Two bands on the skull CT. With 2.5-5.5 the thin plates lie well inside the band. With 2.9-5.4
    // (2.9: the iso-value the sample is named for) their thin partial-volume sheets have D between 0
    // and 0.5, at the band's lower edge: isoatlas (D at voxel centres, as the thesis has it) grows
    // over them and ITK's sparse field stops short, about 10 % of the structure. That case measures
    // how the two schemes differ at the margin.
    {"skull_2.9 bone, band 2.5-5.5", "volumes/skull_2.9.inr", kSkullSeeds, {4.0f, 1.5f, 0.9f}, 8192},
    {"skull_2.9 bone, band 2.9-5.4", "volumes/skull_2.9.inr", kSkullSeeds, {4.15f, 1.25f, 0.9f}, 8192},
};

double dice(const std::vector<char>& a, const std::vector<char>& b) {
  std::int64_t both = 0, sa = 0, sb = 0;
  for (std::size_t n = 0; n < a.size(); ++n) {
    both += a[n] && b[n];
    sa += a[n];
    sb += b[n];
  }
  return sa + sb ? 2.0 * double(both) / double(sa + sb) : 1.0;
}

// Tracks snapshots at 64, 128, 256, ... iterations; done once two in a row agree to Dice 0.999.
// Each solver gets at most this much wall time (ISOATLAS_BENCH_CAP_SECONDS, default 600): one that
// has not converged by then is reported as such, so a ratio against it is a lower bound.
double capSeconds() {
  const char* cap = std::getenv("ISOATLAS_BENCH_CAP_SECONDS");
  return cap ? std::atof(cap) : 600.0;
}

struct Convergence {
  int next = 64;
  std::vector<char> previous;
  int previousIteration = 0;
  double previousSeconds = 0;
  bool converged = false;
  int iterations = 0;
  double seconds = 0;
  std::vector<char> result;
  std::string device;  // the GL renderer the GPU solver ran on; empty for the CPU solvers
  double activeVoxels = 0;  // isoatlas: the mean active voxels an iteration, over the iterations counted
  // Returns true when the run may stop.
  bool snapshot(int iteration, double seconds, std::vector<char> mask) {
    if (!previous.empty() && dice(previous, mask) >= 0.999) {
      converged = true;
      iterations = previousIteration;
      this->seconds = previousSeconds;
      result = std::move(previous);
      return true;
    }
    previous = std::move(mask);
    previousIteration = iteration;
    previousSeconds = seconds;
    next *= 2;
    return false;
  }
};

Image::Pointer toItk(const Volume& v) {
  auto image = Image::New();
  Image::RegionType region;
  region.SetSize({std::size_t(v.dims[0]), std::size_t(v.dims[1]), std::size_t(v.dims[2])});
  image->SetRegions(region);
  image->Allocate();
  const std::vector<float> values = v.toFloat();
  std::copy(values.begin(), values.end(), image->GetBufferPointer());
  return image;
}

// Signed distance to the union of the seed balls, in voxels: negative inside (ITK's sparse field).
Image::Pointer seedDistance(const Volume& v, const Case& c, float sign) {
  auto image = Image::New();
  Image::RegionType region;
  region.SetSize({std::size_t(v.dims[0]), std::size_t(v.dims[1]), std::size_t(v.dims[2])});
  image->SetRegions(region);
  image->Allocate();
  float* out = image->GetBufferPointer();
  for (std::int64_t z = 0; z < v.dims[2]; ++z)
    for (std::int64_t y = 0; y < v.dims[1]; ++y)
      for (std::int64_t x = 0; x < v.dims[0]; ++x) {
        double d = 1e9;
        for (const auto& s : c.seeds)
          d = std::min(d, std::sqrt((x - s[0]) * (x - s[0]) + (y - s[1]) * (y - s[1]) + (z - s[2]) * (z - s[2])) - s[3]);
        out[(z * v.dims[1] + y) * v.dims[0] + x] = sign * float(d);
      }
  return image;
}

std::vector<char> itkMask(const Image* phi, float insideSign) {
  const std::size_t n = phi->GetLargestPossibleRegion().GetNumberOfPixels();
  std::vector<char> mask(n);
  const float* p = phi->GetBufferPointer();
  for (std::size_t i = 0; i < n; ++i) mask[i] = insideSign * p[i] > 0;
  return mask;
}

template <class Filter>
Convergence runItk(Filter* filter, int maxIterations, float insideSign) {
  Convergence conv;
  const auto start = Clock::now();
  int iteration = 0;
  auto observer = itk::CStyleCommand::New();
  struct Context {
    Filter* filter;
    Convergence* conv;
    Clock::time_point start;
    int* iteration;
    float sign;
  } ctx{filter, &conv, start, &iteration, insideSign};
  observer->SetClientData(&ctx);
  observer->SetCallback([](itk::Object*, const itk::EventObject&, void* data) {
    auto* c = static_cast<Context*>(data);
    const int it = int(c->filter->GetElapsedIterations());
    const double seconds = std::chrono::duration<double>(Clock::now() - c->start).count();
    if (seconds > capSeconds()) {
      c->filter->SetNumberOfIterations(unsigned(it));  // out of time: stop unconverged
      return;
    }
    if (it < c->conv->next) return;
    // Halt() stops once the elapsed iterations reach the set number.
    if (c->conv->snapshot(it, seconds, itkMask(c->filter->GetOutput(), c->sign))) c->filter->SetNumberOfIterations(unsigned(it));
  });
  filter->AddObserver(itk::IterationEvent(), observer);
  filter->SetNumberOfIterations(maxIterations);
  filter->Update();
  if (!conv.converged) {
    conv.iterations = int(filter->GetElapsedIterations());
    conv.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    conv.result = itkMask(filter->GetOutput(), insideSign);
  }
  return conv;
}

// halfResolutionStart: start from the solution at half the resolution (pipeline/coarse_start.h), as
// `segment --converge` does; its time is counted in the seconds to convergence.
// topology: Preserve for "-topology" (segment --topology preserve), its cost beside the free front's.
// pagesOnHost: on the GPU, the host applies each iteration's messages (LevelSetOptions::pagesOnDevice
// false, "-host-pages"), to compare with the GPU managing its pages.
Convergence runOurs(const Volume& v, const Case& c, levelset::Backend backend, bool halfResolutionStart = false,
                    levelset::Topology topology = levelset::Topology::Free, bool pagesOnHost = false) {
  // The GPU solver runs in the caller's context, made here before it (so destroyed after it).
  const auto context = backend == levelset::Backend::Gpu ? gl::Context::headless() : nullptr;
  const auto start = Clock::now();
  levelset::LevelSet ls(v, c.params, {.backend = backend, .topology = topology, .pagesOnDevice = !pagesOnHost});
  std::vector<pipeline::Ball> seeds;
  for (const auto& s : c.seeds) seeds.push_back({{s[0], s[1], s[2]}, s[3]});
  if (halfResolutionStart) {
    ls.setMask(pipeline::solveAtHalfResolution(v, c.params, seeds, nullptr, {.backend = backend}, {}).mask);
  } else {
    for (const auto& s : seeds) ls.addSphere(s.centre, s.radius);
  }
  Convergence conv;
  if (context) conv.device = context->info().renderer;
  std::vector<std::size_t> activePages;  // each iteration's, as it ends
  // Runs of at most 64 iterations up to each snapshot (LevelSet::run: on the GPU, the page chain).
  for (int i = 0; i < c.maxIterations;) {
    const int n = std::min({64, conv.next - i, c.maxIterations - i});
    ls.run({.maxIterations = n, .untilConverged = false,
            .progress = [&](int, std::int64_t active) { activePages.push_back(std::size_t(active)); }});
    i += n;
    if (std::chrono::duration<double>(Clock::now() - start).count() > capSeconds()) break;
    if (i < conv.next) continue;
    const Volume m = ls.mask();
    std::vector<char> mask(m.voxelCount());
    for (std::size_t n = 0; n < mask.size(); ++n) mask[n] = m.data[n] != std::byte{0};
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (conv.snapshot(i, seconds, std::move(mask))) break;
  }
  if (!conv.converged) {
    conv.iterations = ls.iterations();
    conv.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    const Volume m = ls.mask();
    conv.result.resize(m.voxelCount());
    for (std::size_t n = 0; n < m.voxelCount(); ++n) conv.result[n] = m.data[n] != std::byte{0};
  }
  const std::size_t counted = std::min(activePages.size(), std::size_t(conv.iterations));
  double pages = 0;
  for (std::size_t i = 0; i < counted; ++i) pages += double(activePages[i]);
  const double P = ls.pages().pageSize();
  conv.activeVoxels = counted ? pages / double(counted) * P * P : 0;
  return conv;
}

// Our solvers: isoatlas-cpu, isoatlas-gpu, and each with "-half-start" or "-topology" (preserved);
// isoatlas-gpu-host-pages.
bool isHalfStart(const std::string& solver) { return solver.ends_with("-half-start"); }
bool isTopology(const std::string& solver) { return solver.ends_with("-topology"); }
bool isHostPages(const std::string& solver) { return solver.ends_with("-host-pages"); }
bool isOurs(const std::string& solver) {
  if (solver == "isoatlas-gpu-host-pages") return true;
  for (const char* s : {"isoatlas-cpu", "isoatlas-gpu"})
    if (solver == s || solver == std::string(s) + "-half-start" || solver == std::string(s) + "-topology") return true;
  return false;
}
// The same backend, free, started from the seeds at full resolution.
std::string fullStartOf(const std::string& solver) { return solver.substr(0, solver.rfind('-')); }

int runOne(const std::string& solver, const Case& c, const Volume& v, const std::string& out) {
  Convergence conv;
  const float lower = c.params.target - c.params.width, upper = c.params.target + c.params.width;
  if (isOurs(solver)) {
    conv = runOurs(v, c, solver.rfind("isoatlas-gpu", 0) == 0 ? levelset::Backend::Gpu : levelset::Backend::Cpu,
                   isHalfStart(solver), isTopology(solver) ? levelset::Topology::Preserve : levelset::Topology::Free,
                   isHostPages(solver));
  } else if (solver == "itk-serial") {
    using Filter = itk::ThresholdSegmentationLevelSetImageFilter<Image, Image>;
    auto f = Filter::New();
    f->SetInput(seedDistance(v, c, 1));
    f->SetFeatureImage(toItk(v));
    f->SetLowerThreshold(lower);
    f->SetUpperThreshold(upper);
    f->SetPropagationScaling(c.params.alpha);
    f->SetCurvatureScaling(1 - c.params.alpha);
    f->SetEdgeWeight(0);
    f->SetMaximumRMSError(0);
    conv = runItk(f.GetPointer(), c.maxIterations, -1);
  } else if (solver == "itk-parallel") {
    using Function = itk::ThresholdSegmentationLevelSetFunction<Image, Image>;
    using Filter = itk::ParallelSparseFieldLevelSetImageFilter<Image, Image>;
    auto fn = Function::New();
    // Initialize first: it resets the weights to (propagation -1, curvature 1, advection 0).
    fn->Initialize(Function::RadiusType{{1, 1, 1}});
    fn->SetFeatureImage(toItk(v));
    fn->SetLowerThreshold(lower);
    fn->SetUpperThreshold(upper);
    fn->SetEdgeWeight(0);
    fn->AllocateSpeedImage();  // as SegmentationLevelSetImageFilter::GenerateData does
    fn->CalculateSpeedImage();
    fn->SetPropagationWeight(c.params.alpha);
    fn->SetCurvatureWeight(1 - c.params.alpha);
    auto f = Filter::New();
    f->SetInput(seedDistance(v, c, 1));  // negative inside, as the serial filter; the output too
    f->SetDifferenceFunction(fn);
    f->SetIsoSurfaceValue(0);
    f->SetNumberOfLayers(3);
    f->SetMaximumRMSError(-1);  // halt by iteration count only
    conv = runItk(f.GetPointer(), c.maxIterations, -1);
  } else {
    std::fprintf(stderr, "bench_levelset: unknown solver %s\n", solver.c_str());
    return 2;
  }
  Volume mask = v.sameGeometry(ScalarType::UInt8);
  for (std::size_t n = 0; n < conv.result.size(); ++n) mask.data[n] = std::byte(conv.result[n] ? 1 : 0);
  writeVolume(out, mask);
  const nlohmann::json j{{"solver", solver}, {"case", c.name}, {"converged", conv.converged},
                         {"iterations", conv.iterations}, {"seconds", conv.seconds},
                         {"ms_per_iteration", conv.iterations ? 1000 * conv.seconds / conv.iterations : 0.0},
                         {"peak_rss_mib", bench::peakRssMiB()}, {"device", conv.device},
                         {"active_voxels_per_iteration", conv.activeVoxels}};
  std::printf("%s\n", j.dump().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 6 && std::string(argv[1]) == "--one") {
    for (const Case& c : kCases)
      if (c.name == argv[3]) return runOne(argv[2], c, readVolume(std::string(argv[4]) + "/" + c.file), argv[5]);
    std::fprintf(stderr, "bench_levelset: unknown case %s\n", argv[3]);
    return 2;
  }
  if (argc == 9 && std::string(argv[1]) == "--one-file") {
    Case c{"given", argv[3], {}, {std::stof(argv[5]), std::stof(argv[6]), std::stof(argv[7])}, 8192};
    std::istringstream seeds(argv[4]);
    for (std::string seed; std::getline(seeds, seed, ';');) {
      std::array<double, 4> s{};
      if (std::sscanf(seed.c_str(), "%lf,%lf,%lf,%lf", &s[0], &s[1], &s[2], &s[3]) != 4) {
        std::fprintf(stderr, "bench_levelset: a seed is x,y,z,r (voxels), not %s\n", seed.c_str());
        return 2;
      }
      c.seeds.push_back(s);
    }
    return runOne(argv[2], c, readVolume(c.file), argv[8]);
  }
  const std::string data = argc > 1 ? argv[1] : "data";
  const std::vector<std::string> only(argv + std::min(argc, 2), argv + argc);  // case names; none: all
  const auto tmp = std::filesystem::temp_directory_path() / "isoatlas-bench-levelset";
  std::filesystem::create_directories(tmp);
  const std::string self = std::filesystem::canonical("/proc/self/exe").string();
  std::vector<std::string> solvers = {"isoatlas-cpu", "isoatlas-cpu-half-start", "isoatlas-cpu-topology", "itk-serial", "itk-parallel"};
  if (std::getenv("ISOATLAS_BENCH_GPU"))
    solvers.insert(solvers.begin() + 3, {"isoatlas-gpu", "isoatlas-gpu-host-pages", "isoatlas-gpu-half-start", "isoatlas-gpu-topology"});
  // ISOATLAS_BENCH_SOLVERS=a,b keeps only those (a GPU lease too short for ITK's serial filter, say).
  if (const char* keep = std::getenv("ISOATLAS_BENCH_SOLVERS")) {
    std::vector<std::string> kept;
    std::istringstream list(keep);
    for (std::string s; std::getline(list, s, ',');) kept.push_back(s);
    std::erase_if(solvers, [&](const std::string& s) { return std::find(kept.begin(), kept.end(), s) == kept.end(); });
  }
  for (const Case& c : kCases) {
    if (!only.empty() && std::find(only.begin(), only.end(), c.name) == only.end()) continue;
    std::map<std::string, nlohmann::json> figures;
    std::map<std::string, Volume> masks;
    for (const std::string& s : solvers) {
      const std::string out = (tmp / (s + ".nii.gz")).string(), log = (tmp / (s + ".json")).string();
      const std::string cmd = "'" + self + "' --one " + s + " '" + c.name + "' '" + data + "' '" + out + "' > '" + log + "'";
      std::fprintf(stderr, "bench_levelset: %s on %s\n", s.c_str(), c.name.c_str());
      if (std::system(cmd.c_str()) != 0) return 1;
      std::ifstream in(log);
      figures[s] = nlohmann::json::parse(in);
      masks[s] = readVolume(out);
      std::fprintf(stderr, "  %s\n", figures[s].dump().c_str());
    }
    auto maskOf = [&](const std::string& s) {
      std::vector<char> m(masks[s].voxelCount());
      for (std::size_t n = 0; n < m.size(); ++n) m[n] = masks[s].data[n] != std::byte{0};
      return m;
    };
    for (const std::string& ours : solvers) {
      if (ours.rfind("isoatlas", 0) != 0) continue;
      // The CPU solver beside the time its memory traffic alone would take (the speed issue's
      // bound): 12 bytes an active voxel an iteration, phi read and written and the source read.
      if (ours == "isoatlas-cpu" && figures[ours]["active_voxels_per_iteration"].get<double>() > 0) {
        static const double bandwidth = bench::memoryBandwidth();
        std::fprintf(stderr, "bench_levelset: memory bandwidth %.2f GB/s (triad, every core), %.0f active voxels an iteration\n",
                     bandwidth / 1e9, figures[ours]["active_voxels_per_iteration"].get<double>());
        const double boundMs = 1000 * 12 * figures[ours]["active_voxels_per_iteration"].get<double>() / bandwidth;
        bench::report("levelset", c.name + ", " + ours, "ms per iteration beside the memory-bandwidth bound", figures[ours]["ms_per_iteration"],
                      "bandwidth bound: 12 bytes an active voxel at the triad bandwidth measured", boundMs, true);
      }
      // The half-resolution start against the full-resolution one: the Dice against today's result.
      if (isHalfStart(ours) && figures.count(fullStartOf(ours))) {
        const std::string full = fullStartOf(ours) + ", started at full resolution";
        const std::string device = figures[ours]["device"].get<std::string>();
        bench::report("levelset", c.name + ", " + ours, "seconds to convergence", figures[ours]["seconds"], full,
                      figures[fullStartOf(ours)]["seconds"], true, device);
        bench::report("levelset", c.name + ", " + ours, "Dice with the peer's result", dice(maskOf(ours), maskOf(fullStartOf(ours))),
                      full, 1.0, false, device);
      }
      // The GPU managing its own pages beside the host applying each iteration's messages: the same
      // phi bit for bit (level_set_test), so Dice 1; the time is what the host's work cost.
      if (isHostPages(ours) && figures.count("isoatlas-gpu")) {
        const std::string device = figures[ours]["device"].get<std::string>();
        const std::string host = "isoatlas-gpu with the host applying each iteration's messages";
        for (const char* figure : {"ms_per_iteration", "seconds"})
          bench::report("levelset", c.name + ", isoatlas-gpu", std::string(figure) == "seconds" ? "seconds to convergence" : "ms per iteration",
                        figures["isoatlas-gpu"][figure], host, figures[ours][figure], true, device);
        bench::report("levelset", c.name + ", isoatlas-gpu", "Dice with the peer's result", dice(maskOf("isoatlas-gpu"), maskOf(ours)), host,
                      1.0, false, device);
        continue;
      }
      // The preserved topology's cost beside the free front on the same backend, and how far its voxels differ.
      if (isTopology(ours) && figures.count(fullStartOf(ours))) {
        const std::string free = fullStartOf(ours) + ", topology free";
        const std::string device = figures[ours]["device"].get<std::string>();
        for (const char* figure : {"ms_per_iteration", "seconds", "iterations"})
          bench::report("levelset", c.name + ", " + ours,
                        std::string(figure) == "seconds" ? "seconds to convergence" : std::string(figure) == "iterations" ? "iterations to convergence" : "ms per iteration",
                        figures[ours][figure], free, figures[fullStartOf(ours)][figure], true, device);
        bench::report("levelset", c.name + ", " + ours, "Dice with the peer's result", dice(maskOf(ours), maskOf(fullStartOf(ours))), free,
                      1.0, false, device);
        continue;  // ITK does not preserve topology: no rows against it
      }
      for (const std::string& peer : {std::string("itk-serial"), std::string("itk-parallel")}) {
        if (!figures.count(peer)) continue;
        const std::string peerName =
            peer == "itk-serial" ? "ITK 5.2 ThresholdSegmentationLevelSet (serial)"
                                 : "ITK 5.2 ParallelSparseField (" +
                                       std::to_string(itk::MultiThreaderBase::GetGlobalDefaultNumberOfThreads()) + " threads)";
        const auto& a = figures[ours];
        const auto& b = figures[peer];
        const std::string device = a["device"].get<std::string>().empty() ? ""
                                   : a["device"].get<std::string>() + " (ITK on " + bench::machineName() + ")";
        const std::string tag = c.name + ", " + ours;
        const std::string unconverged = std::string(a["converged"] ? "" : " (isoatlas: capped, not converged)") +
                                        (b["converged"] ? "" : " (peer: capped, not converged; ratio a lower bound)");
        bench::report("levelset", tag, "seconds to convergence" + unconverged, a["seconds"], peerName, b["seconds"], true, device);
        // The half-resolution start's iterations run on two grids and its seconds hold both: no per-iteration rows.
        if (!isHalfStart(ours)) {
          bench::report("levelset", tag, "ms per iteration", a["ms_per_iteration"], peerName, b["ms_per_iteration"], true, device);
          bench::report("levelset", tag, "iterations to convergence", a["iterations"], peerName, b["iterations"], true, device);
        }
        bench::report("levelset", tag, "peak RSS MiB", a["peak_rss_mib"], peerName, b["peak_rss_mib"], true, device);
        const double d = dice(maskOf(ours), maskOf(peer));
        bench::report("levelset", tag, "Dice with the peer's result", d, peerName, 1.0, false, device);
      }
    }
  }
  return 0;
}
