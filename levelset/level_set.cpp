#include "levelset/level_set.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>

#include "core/error.h"
#include "levelset/cpu_solver.h"
#include "levelset/gpu_solver.h"

namespace isoatlas::levelset {

void validateParams(const SpeedParams& p) {
  require(std::isfinite(p.target), "target T must be a finite number");
  require(std::isfinite(p.width) && p.width > 0, "width eps must be > 0 (got " + std::to_string(p.width) + ")");
  require(std::isfinite(p.alpha) && p.alpha >= 0 && p.alpha <= 1,
          "alpha must lie in [0, 1] (got " + std::to_string(p.alpha) + ")");
}

Topology topologyFor(const std::string& word, const std::string& option) {
  if (word == "free") return Topology::Free;
  if (word == "preserve") return Topology::Preserve;
  throw Error(option + (option.ends_with("=") ? "'" + word + "'" : " " + word) + ": say free or preserve", ErrorKind::BadInput);
}

namespace {

// The volume held in memory as a source (as bytes or floats, as the solvers held it before they read
// a source), once its parameters are valid and its voxels known to be finite.
std::shared_ptr<const VolumeSource> sourceInMemory(const Volume& source, const SpeedParams& params) {
  validateParams(params);
  requireFiniteVoxels(source, "the source volume");
  return VolumeInMemory::compact(source);
}

}  // namespace

LevelSet::LevelSet(const Volume& source, const SpeedParams& params, const LevelSetOptions& options)
    : LevelSet(sourceInMemory(source, params), params, options) {}

LevelSet::LevelSet(std::shared_ptr<const VolumeSource> source, const SpeedParams& params, const LevelSetOptions& options)
    : params_(params), settledChange_(options.settledChange) {
  validateParams(params);
  require(source != nullptr, "the level set has no source volume");
  const Volume& g = source->geometry();
  require(g.voxelCount() > 0, "the source volume is empty");
  require(g.dims[0] <= (1 << 20) && g.dims[1] <= (1 << 20), "volume too wide for the page table");
  geometry_.dims = g.dims;  // the geometry only, not the voxels
  geometry_.spacing = g.spacing;
  geometry_.origin = g.origin;
  geometry_.direction = g.direction;
  pages_ = std::make_unique<PageManager>(g.dims, options.pageSize, options.initialSlots,
                                         options.backend == Backend::Gpu ? PoolLayout::Texture : PoolLayout::Contiguous);
  backend_ = options.backend == Backend::Gpu ? makeGpuSolver(std::move(source), options.topology)
                                             : makeCpuSolver(std::move(source), options.pageSize, options.topology);
  renumberPages_ = options.renumberPages && options.backend != Backend::Gpu;
  pagesOnDevice_ = options.pagesOnDevice && options.backend == Backend::Gpu;
  mark_.assign(std::size_t(pages_->virtualPageCount()), 0);
  movedPage_.assign(std::size_t(pages_->virtualPageCount()), 0);
  wake_.assign(std::size_t(pages_->virtualPageCount()), 0);
  commit({});
}

LevelSet::~LevelSet() = default;

void LevelSet::setParams(const SpeedParams& params) {
  validateParams(params);
  params_ = params;
  wakeAll_ = true;
}

void LevelSet::commit(const std::vector<std::pair<std::int32_t, float>>& filled) {
  backend_->pagesChanged(*pages_, filled);
  physicalBytesPeak_ = std::max(physicalBytesPeak_, backend_->physicalBytes());
}

void LevelSet::addSphere(const Vec3& centre, double radius, bool add) {
  require(std::isfinite(centre.x) && std::isfinite(centre.y) && std::isfinite(centre.z) && std::isfinite(radius) &&
              radius > 0,
          "a sphere needs a finite centre and a radius > 0");
  const int P = pages_->pageSize();
  const auto np = pages_->pages();
  const double reach = radius + kClamp + 1;
  auto pageRange = [&](double c, std::int64_t pagesOnAxis, int size) {
    const std::int64_t lo = std::max<std::int64_t>(0, std::int64_t(std::floor((c - reach) / size)));
    const std::int64_t hi = std::min<std::int64_t>(pagesOnAxis - 1, std::int64_t(std::floor((c + reach) / size)));
    return std::pair{lo, hi};
  };
  const auto [x0, x1] = pageRange(centre.x, np[0], P);
  const auto [y0, y1] = pageRange(centre.y, np[1], P);
  const auto [z0, z1] = pageRange(centre.z, np[2], 1);

  // The sphere's clamped distance transform, > 0 inside.
  auto sphere = [&](double x, double y, double z) {
    const double d = radius - std::sqrt((x - centre.x) * (x - centre.x) + (y - centre.y) * (y - centre.y) +
                                        (z - centre.z) * (z - centre.z));
    return float(std::clamp(d, double(-kClamp), double(kClamp)));
  };
  std::vector<std::pair<std::int32_t, float>> filled;
  std::vector<std::int64_t> touched;
  for (std::int64_t pz = z0; pz <= z1; ++pz)
    for (std::int64_t py = y0; py <= y1; ++py)
      for (std::int64_t px = x0; px <= x1; ++px) {
        // Nearest and farthest points of the page from the centre decide whether the band crosses it.
        const double bx = std::clamp(centre.x, double(px * P), double(px * P + P - 1));
        const double by = std::clamp(centre.y, double(py * P), double(py * P + P - 1));
        const double nearest = std::sqrt((bx - centre.x) * (bx - centre.x) + (by - centre.y) * (by - centre.y) +
                                         (double(pz) - centre.z) * (double(pz) - centre.z));
        double farthest = 0;
        for (int corner = 0; corner < 4; ++corner) {
          const double cx = double(px * P + ((corner & 1) ? P - 1 : 0)), cy = double(py * P + ((corner & 2) ? P - 1 : 0));
          farthest = std::max(farthest, std::sqrt((cx - centre.x) * (cx - centre.x) + (cy - centre.y) * (cy - centre.y) +
                                                  (double(pz) - centre.z) * (double(pz) - centre.z)));
        }
        if (nearest >= radius + kClamp) continue;  // the sphere does not reach this page
        const std::int64_t page = pages_->pageIndex(px, py, pz);
        // Out of the volume is outside: where the inside meets the volume's edge there is a front,
        // so a page on the edge keeps a band (as setMask does) instead of turning static inside.
        const auto& dims = geometry_.dims;
        const bool onEdge = px == 0 || py == 0 || pz == 0 || (px + 1) * P >= dims[0] || (py + 1) * P >= dims[1] ||
                            pz + 1 >= dims[2];
        if (farthest <= radius - kClamp && !pages_->isActive(page) && !(add && onEdge)) {
          pages_->setStatic(page, add);  // wholly inside the sphere's plateau
          continue;
        }
        if (!pages_->isActive(page)) {
          const float was = pages_->staticSlot(page) == kInsideSlot ? kClamp : -kClamp;
          filled.push_back({pages_->activate(page), was});
        }
        touched.push_back(page);
      }
  commit(filled);
  if (touched.empty()) return;
  std::vector<std::int32_t> slots;
  for (std::int64_t page : touched) slots.push_back(pages_->slotOf(page));
  std::vector<float> values = backend_->readSlots(*pages_, slots);
  const std::size_t area = std::size_t(P) * std::size_t(P);
  for (std::size_t i = 0; i < touched.size(); ++i) {
    const auto [px, py, pz] = pages_->pageCoords(touched[i]);
    for (int y = 0; y < P; ++y)
      for (int x = 0; x < P; ++x) {
        const std::int64_t vx = px * P + x, vy = py * P + y;
        float& v = values[i * area + std::size_t(y * P + x)];
        if (vx >= geometry_.dims[0] || vy >= geometry_.dims[1]) continue;  // padding stays outside
        const float s = sphere(double(vx), double(vy), double(pz));
        v = add ? std::max(v, s) : std::min(v, -s);
      }
  }
  backend_->writeSlots(*pages_, slots, values);
  wakeAll_ = true;
}

void LevelSet::setMask(const Volume& mask) {
  require(mask.dims == geometry_.dims, "the seed mask's dimensions differ from the volume's");
  const auto dims = geometry_.dims;
  // Every page starts static; pages where the mask changes (or meets the volume's edge while inside)
  // are activated with the mask's values as +-kClamp. G_r relaxes the step into a distance ramp.
  while (!pages_->activePages().empty()) pages_->release(pages_->activePages().back(), false);
  const int P = pages_->pageSize();
  std::vector<char> boundary(std::size_t(pages_->virtualPageCount()), 0);
  std::vector<char> inside(std::size_t(pages_->virtualPageCount()), 0);
  auto pageOf = [&](std::int64_t x, std::int64_t y, std::int64_t z) { return pages_->pageIndex(x / P, y / P, z); };
  for (std::int64_t z = 0; z < dims[2]; ++z)
    for (std::int64_t y = 0; y < dims[1]; ++y)
      for (std::int64_t x = 0; x < dims[0]; ++x) {
        const bool in = mask.at(x, y, z) > 0;
        const std::int64_t page = pageOf(x, y, z);
        if (in) inside[std::size_t(page)] = 1;
        const std::int64_t n[3][3] = {{x + 1, y, z}, {x, y + 1, z}, {x, y, z + 1}};
        for (const auto& q : n) {
          const bool outOfVolume = q[0] >= dims[0] || q[1] >= dims[1] || q[2] >= dims[2];
          const bool other = outOfVolume ? false : mask.at(q[0], q[1], q[2]) > 0;
          if (other != in || (in && (x == 0 || y == 0 || z == 0))) {
            boundary[std::size_t(page)] = 1;
            if (!outOfVolume) boundary[std::size_t(pageOf(q[0], q[1], q[2]))] = 1;
          }
        }
      }
  std::vector<std::pair<std::int32_t, float>> filled;
  std::vector<std::int64_t> active;
  for (std::int64_t page = 0; page < pages_->virtualPageCount(); ++page) {
    if (boundary[std::size_t(page)]) {
      filled.push_back({pages_->activate(page), -kClamp});
      active.push_back(page);
    } else {
      pages_->setStatic(page, inside[std::size_t(page)] != 0);
    }
  }
  commit(filled);
  std::vector<std::int32_t> slots;
  for (std::int64_t page : active) slots.push_back(pages_->slotOf(page));
  std::vector<float> values(slots.size() * std::size_t(P * P), -kClamp);
  for (std::size_t i = 0; i < active.size(); ++i) {
    const auto [px, py, pz] = pages_->pageCoords(active[i]);
    for (int y = 0; y < P; ++y)
      for (int x = 0; x < P; ++x) {
        const std::int64_t vx = px * P + x, vy = py * P + y;
        if (vx < dims[0] && vy < dims[1] && mask.at(vx, vy, pz) > 0) values[i * std::size_t(P * P) + std::size_t(y * P + x)] = kClamp;
      }
  }
  backend_->writeSlots(*pages_, slots, values);
  wakeAll_ = true;
}

void LevelSet::applyMessages(const IterationResult& r) {
  ++epoch_;
  const auto np = pages_->pages();
  const std::vector<std::int64_t> active = pages_->activePages();  // copy: releases reorder the list
  std::vector<char> insideBit(active.size(), 0);
  std::vector<std::int64_t> requested;
  auto request = [&](std::int64_t page) {
    if (mark_[std::size_t(page)] != epoch_) {
      mark_[std::size_t(page)] = epoch_;
      requested.push_back(page);
    }
  };
  for (std::size_t i = 0; i < active.size(); ++i) {
    const std::uint8_t m = r.messages[i];
    insideBit[i] = (m & kInside) != 0;
    const auto [px, py, pz] = pages_->pageCoords(active[i]);
    if (m & kSelfActive) request(active[i]);
    if ((m & kNeedPlusX) && px + 1 < np[0]) request(pages_->pageIndex(px + 1, py, pz));
    if ((m & kNeedMinusX) && px > 0) request(pages_->pageIndex(px - 1, py, pz));
    if ((m & kNeedPlusY) && py + 1 < np[1]) request(pages_->pageIndex(px, py + 1, pz));
    if ((m & kNeedMinusY) && py > 0) request(pages_->pageIndex(px, py - 1, pz));
    if ((m & kNeedPlusZ) && pz + 1 < np[2]) request(pages_->pageIndex(px, py, pz + 1));
    if ((m & kNeedMinusZ) && pz > 0) request(pages_->pageIndex(px, py, pz - 1));
  }
  bool changed = false;
  for (std::size_t i = 0; i < active.size(); ++i)
    if (mark_[std::size_t(active[i])] != epoch_) {
      pages_->release(active[i], insideBit[i] != 0);
      changed = true;
    }
  std::vector<std::pair<std::int32_t, float>> filled;
  for (std::int64_t page : requested)
    if (!pages_->isActive(page)) {
      const float was = pages_->staticSlot(page) == kInsideSlot ? kClamp : -kClamp;
      filled.push_back({pages_->activate(page), was});
      markMoved(page);
    }
  if (changed || !filled.empty()) commit(filled);
  renumberWhenScattered();
}

// Slots are handed out where they were freed, so as the band moves, the pages beside each other
// scatter over the pool, and the CPU's passes (each page reads its neighbours' rows) wait on memory.
// Once the band has changed by a share of its pages, they are given slots in page order again: a
// copy of the pool, phi the same bit for bit. Not on the GPU: its pool is a texture, which the copy
// would read back (not measured there).
void LevelSet::renumberWhenScattered() {
  constexpr std::int64_t kChangesPerActivePage = 16;  // renumber after active / 16 activations and releases
  const auto active = std::int64_t(pages_->activePages().size());
  if (!renumberPages_ || active == 0 || pages_->changesSinceRenumbering() * kChangesPerActivePage < active) return;
  const auto moves = pages_->renumberInPageOrder();
  std::vector<std::int32_t> oldSlots, newSlots;
  for (const auto& [oldSlot, newSlot] : moves) oldSlots.push_back(oldSlot), newSlots.push_back(newSlot);
  if (!moves.empty()) backend_->writeSlots(*pages_, newSlots, backend_->readSlots(*pages_, oldSlots));
  commit({});  // the active list is sorted even where no slot moved: the backend's per-page tables follow it
}

void LevelSet::markMoved(std::int64_t page) {
  if (!movedPage_[std::size_t(page)]) movedPage_[std::size_t(page)] = 1, movedList_.push_back(page);
}

std::vector<std::uint8_t> LevelSet::pagesToEvaluate() {
  const std::vector<std::int64_t>& active = pages_->activePages();
  std::vector<std::uint8_t> evaluate(active.size(), 1);
  std::vector<std::uint8_t> fromDevice = std::move(evaluateNext_);
  evaluateNext_.clear();
  if (wakeAll_ || !(settledChange_ > 0)) return evaluate;
  if (!fromDevice.empty() || active.empty()) return fromDevice;  // a run on the device found them
  // The moved pages' neighbourhoods marked, then read per active page: the moved pages are the fewer.
  const auto np = pages_->pages();
  std::vector<std::int64_t> woken;
  for (const std::int64_t page : movedList_) {
    const auto [px, py, pz] = pages_->pageCoords(page);
    for (std::int64_t z = std::max<std::int64_t>(pz - 1, 0); z <= std::min(pz + 1, np[2] - 1); ++z)
      for (std::int64_t y = std::max<std::int64_t>(py - 1, 0); y <= std::min(py + 1, np[1] - 1); ++y)
        for (std::int64_t x = std::max<std::int64_t>(px - 1, 0); x <= std::min(px + 1, np[0] - 1); ++x) {
          const std::int64_t n = pages_->pageIndex(x, y, z);
          if (!wake_[std::size_t(n)]) wake_[std::size_t(n)] = 1, woken.push_back(n);
        }
  }
  for (std::size_t i = 0; i < active.size(); ++i) evaluate[i] = wake_[std::size_t(active[i])];
  for (const std::int64_t n : woken) wake_[std::size_t(n)] = 0;
  return evaluate;
}

IterationResult LevelSet::step() {
  const std::vector<std::uint8_t> evaluate = pagesToEvaluate();
  IterationResult r = backend_->iterate(*pages_, params_, evaluate, settledChange_);
  wakeAll_ = false;
  for (const std::int64_t page : movedList_) movedPage_[std::size_t(page)] = 0;
  movedList_.clear();
  const std::vector<std::int64_t>& active = pages_->activePages();
  if (r.moved.size() != active.size())
    throw Error("level set: the backend reported moves for other pages than the active ones", ErrorKind::Failure);
  for (std::size_t i = 0; i < active.size(); ++i)
    if (r.moved[i]) markMoved(active[i]);
  applyMessages(r);
  ++iterations_;
  simulatedTime_ += r.dt;
  return r;
}

bool windowConverged(std::int64_t changesInWindow, std::int64_t activeVoxels, const RunOptions& options) {
  return double(changesInWindow) < std::max(double(options.changedVoxels), options.changedShare * double(activeVoxels));
}

bool LevelSet::runOnDevice(const RunOptions& options, RunStats& stats) {
  if (!pagesOnDevice_ || options.maxIterations <= 0) return false;
  const DeviceRunRequest request{options.maxIterations, options.untilConverged, options.window, double(options.changedVoxels),
                                 options.changedShare, options.progress};
  std::vector<std::uint8_t> evaluate = pagesToEvaluate();
  std::optional<DeviceRun> run = backend_->runOnDevice(*pages_, params_, evaluate, settledChange_, request);
  if (!run) {  // declined: the host's first step evaluates what this run would have
    evaluateNext_ = std::move(evaluate);
    return false;
  }
  wakeAll_ = false;
  for (const std::int64_t page : movedList_) movedPage_[std::size_t(page)] = 0;
  movedList_.clear();
  evaluateNext_ = std::move(run->nextEvaluate);
  for (const float dt : run->dt) simulatedTime_ += dt;
  iterations_ += run->iterations;
  physicalBytesPeak_ = std::max(physicalBytesPeak_, backend_->physicalBytes());
  stats.iterations = run->iterations;
  stats.converged = run->converged;
  stats.bytesReadBackPerIteration = run->iterations ? run->bytesReadBack / std::uint64_t(run->iterations) : 0;
  return true;
}

RunStats LevelSet::run(const RunOptions& options) {
  RunStats stats;
  const auto start = std::chrono::steady_clock::now();
  if (runOnDevice(options, stats)) {
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats.simulatedTime = simulatedTime_;
    return stats;
  }
  std::uint64_t bytes = 0;
  std::deque<std::int64_t> recentSignChanges;  // over the last `window` iterations
  while (stats.iterations < options.maxIterations) {
    const IterationResult r = step();
    ++stats.iterations;
    bytes += r.bytesReadBack;
    recentSignChanges.push_back(r.signChanges);
    if (int(recentSignChanges.size()) > options.window) recentSignChanges.pop_front();
    if (options.progress) options.progress(stats.iterations, std::int64_t(pages_->activePages().size()));
    if (pages_->activePages().empty()) {
      stats.converged = true;  // nothing left that can move
      break;
    }
    if (options.untilConverged && int(recentSignChanges.size()) == options.window) {
      std::int64_t changes = 0;
      for (std::int64_t c : recentSignChanges) changes += c;
      const std::int64_t page = pages_->pageSize(), activeVoxels = std::int64_t(pages_->activePages().size()) * page * page;
      if (windowConverged(changes, activeVoxels, options)) {
        stats.converged = true;
        break;
      }
    }
  }
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  stats.bytesReadBackPerIteration = stats.iterations ? bytes / std::uint64_t(stats.iterations) : 0;
  stats.simulatedTime = simulatedTime_;
  return stats;
}

template <class T, class Convert>
Volume LevelSet::dense(ScalarType type, Convert convert) const {
  Volume out = geometry_.sameGeometry(type);
  auto* data = reinterpret_cast<T*>(out.data.data());
  const int P = pages_->pageSize();
  const auto dims = geometry_.dims;
  std::vector<std::int32_t> slots;
  for (std::int64_t page : pages_->activePages()) slots.push_back(pages_->slotOf(page));
  const std::vector<float> values = backend_->readSlots(*pages_, slots);
  auto writePage = [&](std::int64_t page, auto valueAt) {
    const auto [px, py, pz] = pages_->pageCoords(page);
    for (int y = 0; y < P; ++y)
      for (int x = 0; x < P; ++x) {
        const std::int64_t vx = px * P + x, vy = py * P + y;
        if (vx < dims[0] && vy < dims[1]) data[std::size_t((pz * dims[1] + vy) * dims[0] + vx)] = convert(valueAt(x, y));
      }
  };
  for (std::int64_t page = 0; page < pages_->virtualPageCount(); ++page)
    if (!pages_->isActive(page)) {
      const float v = pages_->staticSlot(page) == kInsideSlot ? kClamp : -kClamp;
      writePage(page, [v](int, int) { return v; });
    }
  const auto& active = pages_->activePages();
  const std::size_t area = std::size_t(P) * std::size_t(P);
  for (std::size_t i = 0; i < active.size(); ++i)
    writePage(active[i], [&](int x, int y) { return values[i * area + std::size_t(y * P + x)]; });
  return out;
}

Volume LevelSet::phi() const {
  return dense<float>(ScalarType::Float32, [](float v) { return v; });
}

Volume LevelSet::mask() const {
  return dense<std::uint8_t>(ScalarType::UInt8, maskValue);
}

Volume maskOf(const Volume& phi) {
  Volume out = phi.sameGeometry(ScalarType::UInt8);
  const auto* phiData = reinterpret_cast<const float*>(phi.data.data());
  for (std::size_t n = 0; n < out.voxelCount(); ++n) out.data[n] = std::byte(maskValue(phiData[n]));
  return out;
}

}  // namespace isoatlas::levelset
