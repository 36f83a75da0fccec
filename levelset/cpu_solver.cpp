#include "levelset/cpu_solver.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include <atomic>

namespace isoatlas::levelset {
namespace {

class CpuSolver final : public SolverBackend {
public:
  CpuSolver(std::vector<float> source, std::array<std::int64_t, 3> dims) : source_(std::move(source)), dims_(dims) {}

  std::string name() const override {
    return "cpu (TBB, " + std::to_string(tbb::info::default_concurrency()) + " threads)";
  }

  void pagesChanged(const PageManager& pm, const std::vector<std::pair<std::int32_t, float>>& filled) override {
    P_ = pm.pageSize();
    width_ = std::size_t(pm.poolPagesX()) * std::size_t(P_);
    const std::size_t texels = width_ * std::size_t(pm.capacity() / pm.poolPagesX()) * std::size_t(P_);
    if (texels > phi_[0].size()) {
      // New rows are appended; existing slots keep their texels.
      const std::size_t old = phi_[0].size();
      for (auto& buffer : phi_) buffer.resize(texels, 0.0f);
      rate_.resize(texels, 0.0f);
      if (old == 0) {
        for (auto& buffer : phi_) {
          fill(buffer, pm, kOutsideSlot, -kClamp);
          fill(buffer, pm, kInsideSlot, kClamp);
        }
      }
    }
    for (const auto& [slot, value] : filled) fill(phi_[current_], pm, slot, value);
    const auto& active = pm.activePages();
    pages_.resize(active.size());
    for (std::size_t i = 0; i < active.size(); ++i) {
      PageInfo& info = pages_[i];
      info.slot = pm.slotOf(active[i]);
      info.coords = pm.pageCoords(active[i]);
      const auto slots = pm.neighbourSlots(active[i]);
      for (int n = 0; n < 27; ++n) info.neighbourOrigins[n] = origin(pm, slots[std::size_t(n)]);
    }
  }

  IterationResult iterate(const PageManager&, const SpeedParams& params) override {
    const std::vector<float>& phi = phi_[current_];
    // Pass 1: speed and rate of change at every voxel of every active page; the largest speed.
    tbb::combinable<float> maxSpeed(0.0f);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pages_.size()), [&](const auto& range) {
      float& localMax = maxSpeed.local();
      float u[27];
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const PageInfo& page = pages_[i];
        forEachVoxel(page, [&](int x, int y, std::int64_t vx, std::int64_t vy, std::int64_t vz) {
          const std::size_t texel = texelOf(page.neighbourOrigins[13], x, y);
          if (vx >= dims_[0] || vy >= dims_[1]) {
            rate_[texel] = 0;
            return;
          }
          gather(phi, page, x, y, u);
          const float intensity = source_[std::size_t((vz * dims_[1] + vy) * dims_[0] + vx)];
          const VoxelUpdate update = evaluateVoxel(u, intensity, params);
          rate_[texel] = update.rate;
          if (update.rate != 0) localMax = std::max(localMax, std::fabs(update.speed));
        });
      }
    });
    IterationResult result;
    result.maxSpeed = maxSpeed.combine([](float a, float b) { return std::max(a, b); });
    result.dt = timeStep(result.maxSpeed, params.alpha);

    // Pass 2: explicit Euler step into the other copy, clamped; count sign changes.
    std::vector<float>& next = phi_[1 - current_];
    std::atomic<std::int64_t> signChanges{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pages_.size()), [&](const auto& range) {
      std::int64_t changes = 0;
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        const PageInfo& page = pages_[i];
        forEachVoxel(page, [&](int x, int y, std::int64_t vx, std::int64_t vy, std::int64_t) {
          const std::size_t texel = texelOf(page.neighbourOrigins[13], x, y);
          // Voxels past the volume's edge (in partial pages) stay outside: the volume is padded with outside.
          const float value = vx >= dims_[0] || vy >= dims_[1]
                                  ? -kClamp
                                  : std::clamp(phi[texel] + result.dt * rate_[texel], -kClamp, kClamp);
          changes += (value > 0) != (phi[texel] > 0);
          next[texel] = value;
        });
      }
      signChanges += changes;
    });
    current_ = 1 - current_;
    result.signChanges = signChanges;

    // Pass 3: the activation message of every page, from the new phi.
    result.messages.assign(pages_.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pages_.size()), [&](const auto& range) {
      float u[27];
      for (std::size_t i = range.begin(); i != range.end(); ++i)
        result.messages[i] = message(phi_[current_], pages_[i], u);
    });
    return result;
  }

  std::vector<float> readSlots(const PageManager& pm, const std::vector<std::int32_t>& slots) override {
    const std::size_t area = std::size_t(P_) * std::size_t(P_);
    std::vector<float> out(slots.size() * area);
    for (std::size_t s = 0; s < slots.size(); ++s) {
      const auto o = origin(pm, slots[s]);
      for (int y = 0; y < P_; ++y)
        for (int x = 0; x < P_; ++x) out[s * area + std::size_t(y * P_ + x)] = phi_[current_][texelOf(o, x, y)];
    }
    return out;
  }

  void writeSlots(const PageManager& pm, const std::vector<std::int32_t>& slots, const std::vector<float>& values) override {
    const std::size_t area = std::size_t(P_) * std::size_t(P_);
    for (std::size_t s = 0; s < slots.size(); ++s) {
      const auto o = origin(pm, slots[s]);
      for (int y = 0; y < P_; ++y)
        for (int x = 0; x < P_; ++x) phi_[current_][texelOf(o, x, y)] = values[s * area + std::size_t(y * P_ + x)];
    }
  }

  std::uint64_t physicalBytes() const override {
    return (phi_[0].size() * 2 + rate_.size()) * sizeof(float) + pages_.size() * sizeof(PageInfo);
  }

private:
  using Origin = std::array<std::int32_t, 2>;
  struct PageInfo {
    std::int32_t slot;
    std::array<std::int64_t, 3> coords;
    Origin neighbourOrigins[27];  // index 13 is the page itself
  };

  static Origin origin(const PageManager& pm, std::int32_t slot) { return pm.slotOrigin(slot); }
  std::size_t texelOf(const Origin& o, int x, int y) const {
    return std::size_t(o[1] + y) * width_ + std::size_t(o[0] + x);
  }

  void fill(std::vector<float>& buffer, const PageManager& pm, std::int32_t slot, float value) const {
    const Origin o = origin(pm, slot);
    for (int y = 0; y < P_; ++y)
      for (int x = 0; x < P_; ++x) buffer[texelOf(o, x, y)] = value;
  }

  template <class Fn>
  void forEachVoxel(const PageInfo& page, Fn&& fn) const {
    for (int y = 0; y < P_; ++y)
      for (int x = 0; x < P_; ++x)
        fn(x, y, page.coords[0] * P_ + x, page.coords[1] * P_ + y, page.coords[2]);
  }

  // The 3x3x3 neighbourhood of voxel (x, y) of `page`, through its neighbour table only.
  void gather(const std::vector<float>& phi, const PageInfo& page, int x, int y, float* u) const {
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          int lx = x + dx, ly = y + dy;
          const int ox = lx < 0 ? -1 : (lx >= P_ ? 1 : 0), oy = ly < 0 ? -1 : (ly >= P_ ? 1 : 0);
          lx -= ox * P_;
          ly -= oy * P_;
          const Origin& o = page.neighbourOrigins[(dz + 1) * 9 + (oy + 1) * 3 + (ox + 1)];
          u[(dz + 1) * 9 + (dy + 1) * 3 + (dx + 1)] = phi[texelOf(o, lx, ly)];
        }
  }

  // Which pages must be active next: this one if any voxel differs from a face neighbour; a
  // neighbour page if a voxel on the shared border differs from its voxel across it.
  std::uint8_t message(const std::vector<float>& phi, const PageInfo& page, float* u) const {
    std::uint8_t bits = 0;
    forEachVoxel(page, [&](int x, int y, std::int64_t, std::int64_t, std::int64_t) {
      gather(phi, page, x, y, u);
      const float c = u[13];
      const bool px = u[14] != c, mx = u[12] != c, py = u[16] != c, my = u[10] != c, pz = u[22] != c, mz = u[4] != c;
      if (px || mx || py || my || pz || mz) bits |= kSelfActive;
      if (px && x == P_ - 1) bits |= kNeedPlusX;
      if (mx && x == 0) bits |= kNeedMinusX;
      if (py && y == P_ - 1) bits |= kNeedPlusY;
      if (my && y == 0) bits |= kNeedMinusY;
      if (pz) bits |= kNeedPlusZ;
      if (mz) bits |= kNeedMinusZ;
    });
    if (phi[texelOf(page.neighbourOrigins[13], 0, 0)] > 0) bits |= kInside;
    return bits;
  }

  std::vector<float> source_;
  std::array<std::int64_t, 3> dims_;
  std::vector<float> phi_[2], rate_;
  int current_ = 0, P_ = 16;
  std::size_t width_ = 0;
  std::vector<PageInfo> pages_;
};

}  // namespace

std::unique_ptr<SolverBackend> makeCpuSolver(std::vector<float> source, std::array<std::int64_t, 3> dims) {
  return std::make_unique<CpuSolver>(std::move(source), dims);
}

}  // namespace isoatlas::levelset
