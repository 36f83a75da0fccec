#include "levelset/cpu_solver.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>

#include "core/error.h"
#include "core/huge_pages.h"
#include "levelset/row_stencil.h"
#include "levelset/simple_point.h"

namespace isoatlas::levelset {
namespace {

// A page's neighbour at (dy, dz) in {-1, 0, 1}^2 in the tables of PageInfo (which say its dx).
constexpr int besideAt(int dy, int dz) { return (dz + 1) * 3 + dy + 1; }
constexpr int kSelf = besideAt(0, 0);

class CpuSolver final : public SolverBackend {
public:
  CpuSolver(std::shared_ptr<const VolumeSource> source, int pageSize, Topology topology)
      : source_(std::move(source)), dims_(source_->geometry().dims), pagesX_((dims_[0] + pageSize - 1) / pageSize),
        pagesY_((dims_[1] + pageSize - 1) / pageSize), topology_(topology), P_(pageSize), bytes_(source_->wholeBytes()) {
    sourceOf_.assign(std::size_t(pagesX_ * pagesY_ * dims_[2]), -1);
    isActive_.assign(sourceOf_.size(), 0);
  }

  std::string name() const override {
    return "cpu (TBB, " + std::to_string(tbb::info::default_concurrency()) + " threads)";
  }

  void pagesChanged(const PageManager& pm, const std::vector<std::pair<std::int32_t, float>>& filled) override {
    require(pm.pageSize() == P_, "the CPU solver was made for pages of " + std::to_string(P_));
    width_ = std::size_t(pm.poolPagesX()) * std::size_t(P_);
    const std::size_t texels = width_ * std::size_t(pm.capacity() / pm.poolPagesX()) * std::size_t(P_);
    if (texels > phi_.size()) {
      // New rows are appended; existing slots keep their texels.
      const std::size_t old = phi_.size();
      phi_.resize(texels, 0.0f);
      edges_.resize(std::size_t(pm.capacity()) * 2 * std::size_t(P_));
      if (old == 0) {
        fill(pm, kOutsideSlot, -kClamp);
        fill(pm, kInsideSlot, kClamp);
      }
    }
    for (const auto& [slot, value] : filled) fill(pm, slot, value);
    const auto& active = pm.activePages();
    keepSourcesOf(active);
    pages_.resize(active.size());
    for (std::size_t i = 0; i < active.size(); ++i) {
      PageInfo& info = pages_[i];
      info.slot = pm.slotOf(active[i]);
      info.source = sourceOf_[std::size_t(active[i])];
      info.coords = pm.pageCoords(active[i]);
      const auto slots = pm.neighbourSlots(active[i]);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy) {
          const std::size_t west = std::size_t((dz + 1) * 9 + (dy + 1) * 3);  // neighbourSlots' order
          const int k = besideAt(dy, dz);
          info.westEdges[k] = edgesOf(slots[west]);
          info.origins[k] = origin(pm, slots[west + 1]);
          info.eastEdges[k] = edgesOf(slots[west + 2]);
        }
    }
    if (topology_ == Topology::Preserve) {
      around_.resize(active.size());
      for (std::size_t i = 0; i < active.size(); ++i) {
        const auto slots = pm.neighbourSlots(active[i]);
        for (std::size_t n = 0; n < 27; ++n) around_[i][n] = origin(pm, slots[n]);
      }
    }
  }

  IterationResult iterate(const PageManager& pm, const SpeedParams& params, const std::vector<std::uint8_t>& evaluate,
                          float settledChange) override {
    requireTablesFollow(pm);
    Pool& phi = phi_;
    // Pass 1: speed and rate of change at every voxel of the rows that can change (some voxel differs
    // from a face neighbour) of the pages evaluated; the largest speed. Only voxels that move are
    // listed for pass 2.
    tbb::combinable<float> maxSpeed(0.0f);
    moving_.resize(pages_.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pages_.size()), [&](const auto& range) {
      float& localMax = maxSpeed.local();
      Apron apron(P_);
      Moving moves[kMaxPageSize * kMaxPageSize];
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        if (!evaluate[i]) {  // settled
          moving_[i].clear();
          continue;
        }
        const PageInfo& page = pages_[i];
        apron.load(*this, phi, page);
        int moved = 0;
        const int rows = rowsIn(page), xEnd = columnsIn(page);
        for (int y0 = 0; y0 < rows;) {
          if (apron.flatRow(y0, xEnd)) {
            ++y0;
            continue;
          }
          int y1 = y0 + 1;
          while (y1 < rows && !apron.flatRow(y1, xEnd)) ++y1;
          moved = evaluateRun(apron, page, y0, y1, params, moves, moved, localMax);
          y0 = y1;
        }
        moving_[i].assign(moves, moves + moved);
      }
    });
    IterationResult result;
    result.maxSpeed = maxSpeed.combine([](float a, float b) { return std::max(a, b); });
    result.dt = timeStep(result.maxSpeed, params.alpha);

    // Pass 2: explicit Euler step, clamped; count sign changes; which pages changed by more than
    // settledChange. Pass 1 has read everything, so the update is in place (the GPU ping-pongs
    // instead) and visits only the voxels that move.
    // With the topology preserved, a voxel that would change side waits in sideChanges_ for pass 2b.
    std::atomic<std::int64_t> signChanges{0};
    const bool preserve = topology_ == Topology::Preserve;
    result.moved.assign(pages_.size(), 0);
    if (preserve) sideChanges_.resize(pages_.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pages_.size()), [&](const auto& range) {
      std::int64_t changes = 0;
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        bool moved = false;
        if (preserve) sideChanges_[i].clear();
        for (const Moving& m : moving_[i]) {
          float& value = phi[m.texel];
          const float next = std::clamp(value + result.dt * m.rate, -kClamp, kClamp);
          if (preserve && (next > 0) != (value > 0)) {
            sideChanges_[i].push_back({m.texel, next});
            continue;
          }
          changes += (next > 0) != (value > 0);
          moved |= std::fabs(next - value) > settledChange;
          value = next;
        }
        // Each page refreshes its own slot's column copy; none is read before pass 3 (with the
        // topology preserved, pass 2b refreshes it again where it changes a voxel).
        if (!moving_[i].empty()) refreshEdges(pages_[i].slot, pages_[i].origins[kSelf]);
        result.moved[i] = moved;
      }
      signChanges += changes;
    });
    result.signChanges = signChanges;
    if (preserve) result.signChanges += changeSidesWhereSimple(phi, settledChange, result.moved);

    // Pass 3: the activation message of every page, from the new phi.
    result.messages.assign(pages_.size(), 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pages_.size()), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) result.messages[i] = message(phi, pages_[i]);
    });
    return result;
  }

  std::vector<float> readSlots(const PageManager& pm, const std::vector<std::int32_t>& slots) override {
    const std::size_t area = std::size_t(P_) * std::size_t(P_);
    std::vector<float> out(slots.size() * area);
    for (std::size_t s = 0; s < slots.size(); ++s) {
      const auto o = origin(pm, slots[s]);
      for (int y = 0; y < P_; ++y)
        for (int x = 0; x < P_; ++x) out[s * area + std::size_t(y * P_ + x)] = phi_[texelOf(o, x, y)];
    }
    return out;
  }

  void writeSlots(const PageManager& pm, const std::vector<std::int32_t>& slots, const std::vector<float>& values) override {
    const std::size_t area = std::size_t(P_) * std::size_t(P_);
    for (std::size_t s = 0; s < slots.size(); ++s) {
      const auto o = origin(pm, slots[s]);
      for (int y = 0; y < P_; ++y)
        for (int x = 0; x < P_; ++x) phi_[texelOf(o, x, y)] = values[s * area + std::size_t(y * P_ + x)];
      refreshEdges(slots[s], o);
    }
  }

  const float* phiPoolOnHost() override { return phi_.data(); }

  std::uint64_t physicalBytes() const override {
    std::size_t moving = 0;
    for (const auto& m : moving_) moving += m.capacity();
    return (phi_.size() + edges_.size()) * sizeof(float) + moving * sizeof(Moving) + pages_.size() * sizeof(PageInfo) +
           around_.size() * sizeof(around_[0]) +
           sourceFloats_.size() * sizeof(float) + sourceBytes_.size() + sourceOf_.size() * (sizeof(std::int32_t) + 1) +
           kept_.capacity() * sizeof(std::int64_t) + freeSources_.capacity() * sizeof(std::int32_t) + source_->heldBytes();
  }

private:
  // The pool and the source are read a page here and a page there: huge pages spare the TLB.
  using Pool = HugePageVector<float>;
  using Origin = std::array<std::int32_t, 2>;
  struct PageInfo {
    std::int32_t slot;
    std::int32_t source;  // where its intensities lie in sourceBytes_ or sourceFloats_, in pages
    std::array<std::int64_t, 3> coords;
    // The pages beside it at dx = 0 (origins, the page itself at kSelf), and where those at dx = -1
    // and +1 keep their edge columns in edges_: the only parts of the 27 that are read.
    Origin origins[9];
    std::uint32_t westEdges[9], eastEdges[9];
  };

  struct Moving {
    std::uint32_t texel;
    float rate;
  };
  struct SideChange {
    std::uint32_t texel;
    float next;  // the step's value, on the other side
  };

  static Origin origin(const PageManager& pm, std::int32_t slot) { return pm.slotOrigin(slot); }
  // The per-page tables are in the active list's order as pagesChanged last saw it: a list reordered
  // or a slot moved since, without pagesChanged, would credit each page with another's results.
  void requireTablesFollow(const PageManager& pm) const {
    const auto& active = pm.activePages();
    bool follow = pages_.size() == active.size();
    for (std::size_t i = 0; i < pages_.size() && follow; ++i) follow = pages_[i].slot == pm.slotOf(active[i]);
    if (!follow) throw Error("CPU level set: the active pages changed without pagesChanged", ErrorKind::Failure);
  }
  std::size_t texelOf(const Origin& o, int x, int y) const {
    return std::size_t(o[1] + y) * width_ + std::size_t(o[0] + x);
  }

  void fill(const PageManager& pm, std::int32_t slot, float value) {
    const Origin o = origin(pm, slot);
    for (int y = 0; y < P_; ++y)
      for (int x = 0; x < P_; ++x) phi_[texelOf(o, x, y)] = value;
    refreshEdges(slot, o);
  }

  // Each slot's first and last columns, copied out of phi_ (P floats each, one after the other): the
  // pages beside it across x read these, a cache line or two, where the column in place lies across
  // P lines. Every write to phi_ refreshes the slot's copy.
  std::uint32_t edgesOf(std::int32_t slot) const { return std::uint32_t(slot) * 2u * std::uint32_t(P_); }
  const float* firstColumn(std::uint32_t edgesAt) const { return &edges_[edgesAt]; }
  const float* lastColumn(std::uint32_t edgesAt) const { return &edges_[edgesAt + std::uint32_t(P_)]; }
  void refreshEdges(std::int32_t slot, const Origin& o) {
    float* first = &edges_[edgesOf(slot)];
    for (int y = 0; y < P_; ++y) {
      first[y] = phi_[texelOf(o, 0, y)];
      first[P_ + y] = phi_[texelOf(o, P_ - 1, y)];
    }
  }

  // The (P+2) x (P+2) x 3 values around a page, read through its neighbour table only (as the GPU
  // reads them into shared memory; the x neighbours' columns from their copies in edges_); voxels
  // are then evaluated without further lookups.
  struct Apron {
    int side;
    std::array<float, 3 * (kMaxPageSize + 2) * (kMaxPageSize + 2)> v;  // [dz][y + 1][x + 1]
    explicit Apron(int P) : side(P + 2) {}
    void load(const CpuSolver& s, const Pool& phi, const PageInfo& page) {
      // Rows of a size known when compiled are copied inline instead of by a library call per row:
      // a fixed-size memcpy is inlined (std::copy_n compiled to a call to memmove).
      switch (side - 2) {
        case 4: return loadRows<4>(s, phi, page);
        case 8: return loadRows<8>(s, phi, page);
        case 16: return loadRows<16>(s, phi, page);
        default: return loadRows<kMaxPageSize>(s, phi, page);
      }
    }
    template <int P>
    void loadRows(const CpuSolver& s, const Pool& phi, const PageInfo& page) {
      static_assert(P <= kMaxPageSize);
      for (int dz = -1; dz <= 1; ++dz)
        for (int y = -1; y <= P; ++y) {
          const int oy = y < 0 ? -1 : (y >= P ? 1 : 0), ly = y - oy * P;
          const int k = besideAt(oy, dz);  // the row's page
          float* out = &v[std::size_t(((dz + 1) * side + y + 1) * side)];
          out[0] = s.lastColumn(page.westEdges[k])[ly];
          std::memcpy(out + 1, &phi[s.texelOf(page.origins[k], 0, ly)], P * sizeof(float));
          out[P + 1] = s.firstColumn(page.eastEdges[k])[ly];
        }
    }
    const float* row(int y, int dz) const { return &v[std::size_t(((dz + 1) * side + y + 1) * side + 1)]; }
    // Whether every voxel x < xEnd of row y equals its six face neighbours. Branch-free, so it vectorises.
    bool flatRow(int y, int xEnd) const {
      const float *c = row(y, 0), *ym = row(y - 1, 0), *yp = row(y + 1, 0), *zm = row(y, -1), *zp = row(y, 1);
      unsigned differs = 0;  // accumulated in an integer, so that the loop vectorises
      for (int x = 0; x < xEnd; ++x)
        differs |= unsigned(c[x + 1] != c[x]) | unsigned(c[x - 1] != c[x]) | unsigned(yp[x] != c[x]) |
                   unsigned(ym[x] != c[x]) | unsigned(zp[x] != c[x]) | unsigned(zm[x] != c[x]);
      return differs == 0;
    }
  };

  // Rows inside the volume (those past its edge are kept outside) and columns, of a page.
  int rowsIn(const PageInfo& page) const { return int(std::min<std::int64_t>(P_, dims_[1] - page.coords[1] * P_)); }
  int columnsIn(const PageInfo& page) const { return int(std::min<std::int64_t>(P_, dims_[0] - page.coords[0] * P_)); }

  // Speed and rate of rows y0 <= y < y1 of a page (the whole rows, which is faster than only the
  // voxels that can move). The voxels that move are appended to moves[moved..] with their rate, and
  // the largest speed among them kept in localMax: a flat voxel's rate is 0 (every one-sided
  // difference is), so rate alone says which move. Returns the new count.
  int evaluateRun(const Apron& apron, const PageInfo& page, int y0, int y1, const SpeedParams& params, Moving* moves,
                  int moved, float& localMax) const {
    float faces[(kMaxPageSize + 1) * kMaxPageSize], speed[kMaxPageSize * kMaxPageSize], rate[kMaxPageSize * kMaxPageSize];
    const int xEnd = columnsIn(page);
    float scratch[kMaxPageSize * kMaxPageSize];
    const float* intensity = intensities(page, y0, y1, scratch);
    rowFaceNormals(apron.v.data(), apron.side, y0 - 1, y1, xEnd, faces);
    std::uint32_t movingInRow[kMaxPageSize];
    evaluateRows(apron.v.data(), apron.side, y0, y1, xEnd, intensity, std::size_t(P_), params, faces,
                 std::size_t(kMaxPageSize), speed, rate, movingInRow);
    for (int y = y0; y < y1; ++y) {
      const float* s = speed + std::size_t(y - y0) * kMaxPageSize;
      const float* r = rate + std::size_t(y - y0) * kMaxPageSize;
      const std::uint32_t rowStart = std::uint32_t(texelOf(page.origins[kSelf], 0, y));
      for (std::uint32_t moving = movingInRow[y - y0]; moving; moving &= moving - 1) {  // about a quarter move
        const int x = std::countr_zero(moving);
        moves[moved++] = {rowStart + std::uint32_t(x), r[x]};
        localMax = std::max(localMax, std::fabs(s[x]));
      }
    }
    return moved;
  }

  // Pass 2b: the voxels waiting to change side, parity class by parity class of their (x, y, z):
  // each changes where it is a simple point of the object as the classes before left it, and is
  // held on its side, kHeldOffFront from the front, where not. Returns the voxels that changed side;
  // sets moved[i] where page i's changed by more than settledChange.
  std::int64_t changeSidesWhereSimple(Pool& phi, float settledChange, std::vector<std::uint8_t>& moved) {
    std::atomic<std::int64_t> changes{0};
    for (int parity = 0; parity < 8; ++parity)
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pages_.size()), [&](const auto& range) {
        std::int64_t local = 0;
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          bool changed = false;
          for (const SideChange& c : sideChanges_[i]) {
            const auto [x, y] = localOf(pages_[i], c.texel);
            const std::int64_t gx = pages_[i].coords[0] * P_ + x, gy = pages_[i].coords[1] * P_ + y, gz = pages_[i].coords[2];
            if (int(gx & 1) + 2 * int(gy & 1) + 4 * int(gz & 1) != parity) continue;
            float& value = phi[c.texel];
            const float next = isSimplePoint(insideAround(phi, i, x, y)) ? c.next : (value > 0 ? kHeldOffFront : -kHeldOffFront);
            local += (next > 0) != (value > 0);
            moved[i] |= std::fabs(next - value) > settledChange;
            changed |= next != value;
            value = next;
          }
          if (changed) refreshEdges(pages_[i].slot, pages_[i].origins[kSelf]);
        }
        changes += local;
      });
    return changes;
  }
  // Where texel lies in page i: its column and row.
  std::pair<int, int> localOf(const PageInfo& page, std::uint32_t texel) const {
    const Origin& o = page.origins[kSelf];
    return {int(texel % width_) - o[0], int(texel / width_) - o[1]};
  }
  // The inside bits of voxel (x, y) of page i's 3 x 3 x 3 (simple_point.h's order), read through
  // the page's 27 neighbours; past the volume's edge is outside.
  std::uint32_t insideAround(const Pool& phi, std::size_t i, int x, int y) const {
    const PageInfo& page = pages_[i];
    return insideBits([&](int dx, int dy, int dz) {
      const int lx = x + dx, ly = y + dy;
      const std::int64_t gx = page.coords[0] * P_ + lx, gy = page.coords[1] * P_ + ly, gz = page.coords[2] + dz;
      if (gx < 0 || gy < 0 || gz < 0 || gx >= dims_[0] || gy >= dims_[1] || gz >= dims_[2]) return false;
      const int ox = lx < 0 ? -1 : (lx >= P_ ? 1 : 0), oy = ly < 0 ? -1 : (ly >= P_ ? 1 : 0);
      const Origin& o = around_[i][std::size_t((dz + 1) * 9 + (oy + 1) * 3 + ox + 1)];
      return phi[texelOf(o, lx - ox * P_, ly - oy * P_)] > 0;
    });
  }

  // Which pages must be active next: this one if any voxel differs from a face neighbour; a
  // neighbour page if a voxel on the shared border differs from its voxel across it. Rows are read
  // in place through the neighbour table, the x neighbours' columns from their copies (no apron:
  // only face neighbours are compared), and the comparisons accumulate in integers so that each
  // row's loop vectorises.
  std::uint8_t message(const Pool& phi, const PageInfo& page) const {
    const Origin* o = page.origins;  // [besideAt(dy, dz)]
    const int P = P_;
    const float *plusX = firstColumn(page.eastEdges[kSelf]), *minusX = lastColumn(page.westEdges[kSelf]);
    unsigned self = 0, px = 0, mx = 0, py = 0, my = 0, pz = 0, mz = 0;
    for (int y = 0; y < P; ++y) {
      const float* c = &phi[texelOf(o[kSelf], 0, y)];
      const float* zp = &phi[texelOf(o[besideAt(0, 1)], 0, y)];
      const float* zm = &phi[texelOf(o[besideAt(0, -1)], 0, y)];
      const float* yp = y + 1 < P ? c + width_ : &phi[texelOf(o[besideAt(1, 0)], 0, 0)];
      const float* ym = y > 0 ? c - width_ : &phi[texelOf(o[besideAt(-1, 0)], 0, P - 1)];
      unsigned rowSelf = 0, rowPz = 0, rowMz = 0, rowYp = 0, rowYm = 0;
      for (int x = 0; x < P; ++x) {
        rowPz |= zp[x] != c[x];
        rowMz |= zm[x] != c[x];
        rowYp |= yp[x] != c[x];
        rowYm |= ym[x] != c[x];
      }
      for (int x = 0; x + 1 < P; ++x) rowSelf |= c[x + 1] != c[x];
      self |= rowSelf | rowPz | rowMz | rowYp | rowYm;
      pz |= rowPz;
      mz |= rowMz;
      if (y == P - 1) py = rowYp;
      if (y == 0) my = rowYm;
      px |= plusX[y] != c[P - 1];
      mx |= minusX[y] != c[0];
    }
    self |= px | mx;
    std::uint8_t bits = 0;
    if (self) bits |= kSelfActive;
    if (px) bits |= kNeedPlusX;
    if (mx) bits |= kNeedMinusX;
    if (py) bits |= kNeedPlusY;
    if (my) bits |= kNeedMinusY;
    if (pz) bits |= kNeedPlusZ;
    if (mz) bits |= kNeedMinusZ;
    if (phi[texelOf(o[kSelf], 0, 0)] > 0) bits |= kInside;
    return bits;
  }

  // The source's intensities of the active pages, each page's P x P together, x fastest, so that
  // pass 1 reads a page's in a few neighbouring cache lines: read from the source when a page becomes
  // active, given back when it stops (kept apart from phi's slots, which renumbering moves).
  void keepSourcesOf(const std::vector<std::int64_t>& active) {
    const std::size_t area = std::size_t(P_) * std::size_t(P_);
    for (const std::int64_t page : active) isActive_[std::size_t(page)] = 1;
    std::erase_if(kept_, [&](std::int64_t page) {
      if (isActive_[std::size_t(page)]) return false;
      freeSources_.push_back(sourceOf_[std::size_t(page)]);
      sourceOf_[std::size_t(page)] = -1;
      return true;
    });
    for (const std::int64_t page : active) isActive_[std::size_t(page)] = 0;
    std::vector<float> row(static_cast<std::size_t>(P_), 0.0f);
    for (const std::int64_t page : active) {
      std::int32_t& at = sourceOf_[std::size_t(page)];
      if (at >= 0) continue;
      if (freeSources_.empty()) {  // room for a quarter more pages
        const std::size_t held = (bytes_ ? sourceBytes_.size() : sourceFloats_.size()) / area, grown = held + held / 4 + 16;
        if (bytes_) sourceBytes_.resize(grown * area, 0);
        else sourceFloats_.resize(grown * area, 0.0f);
        for (std::size_t k = grown; k-- > held;) freeSources_.push_back(std::int32_t(k));
      }
      const std::int32_t store = freeSources_.back();
      // Its rows from the source (past the volume's edge 0, never read), then the page marked as held,
      // so that a source that throws leaves nothing half read.
      const std::int64_t px = page % pagesX_, py = page / pagesX_ % pagesY_, z = page / (pagesX_ * pagesY_);
      const std::int64_t x0 = px * P_, n = std::min<std::int64_t>(P_, dims_[0] - x0);
      for (int y = 0; y < P_; ++y) {
        std::fill(row.begin(), row.end(), 0.0f);
        if (py * P_ + y < dims_[1]) source_->readRow(x0, py * P_ + y, z, n, row.data());
        const std::size_t to = (std::size_t(store) * std::size_t(P_) + std::size_t(y)) * std::size_t(P_);
        if (bytes_) std::transform(row.begin(), row.end(), &sourceBytes_[to], [](float v) { return std::uint8_t(v); });
        else std::copy(row.begin(), row.end(), &sourceFloats_[to]);
      }
      freeSources_.pop_back();
      at = store;
      kept_.push_back(page);
    }
  }
  // Rows y0 <= y < y1 of a page's intensities (P a row), as floats: in place, or from bytes into scratch.
  const float* intensities(const PageInfo& page, int y0, int y1, float* scratch) const {
    const std::size_t from = (std::size_t(page.source) * std::size_t(P_) + std::size_t(y0)) * std::size_t(P_);
    if (!bytes_) return &sourceFloats_[from];
    const std::uint8_t* bytes = &sourceBytes_[from];
    for (std::size_t k = 0, n = std::size_t(y1 - y0) * std::size_t(P_); k < n; ++k) scratch[k] = float(bytes[k]);
    return scratch;
  }

  std::shared_ptr<const VolumeSource> source_;
  std::array<std::int64_t, 3> dims_;
  std::int64_t pagesX_, pagesY_;
  // The active pages' intensities (keepSourcesOf): as bytes where every intensity is a whole number
  // from 0 to 255, as in most MRI volumes (a quarter of the memory to wait on, the same floats read),
  // else as floats; per virtual page, where its intensities lie (-1: none).
  HugePageVector<std::uint8_t> sourceBytes_;
  Pool sourceFloats_;
  std::vector<std::int32_t> sourceOf_, freeSources_;
  std::vector<std::int64_t> kept_;  // the pages holding intensities
  std::vector<std::uint8_t> isActive_;  // per virtual page, scratch for keepSourcesOf (all 0 between calls)
  Pool phi_;
  std::vector<float> edges_;  // per slot, its first and last columns (refreshEdges)
  std::vector<std::vector<Moving>> moving_;  // per active page, from pass 1
  Topology topology_;
  std::vector<std::vector<SideChange>> sideChanges_;  // per active page, pass 2's for pass 2b (Preserve)
  std::vector<std::array<Origin, 27>> around_;        // per active page, its 3 x 3 x 3's origins (Preserve)
  int P_ = 16;
  bool bytes_ = false;
  std::size_t width_ = 0;
  std::vector<PageInfo> pages_;
};

}  // namespace

std::unique_ptr<SolverBackend> makeCpuSolver(std::shared_ptr<const VolumeSource> source, int pageSize, Topology topology) {
  return std::make_unique<CpuSolver>(std::move(source), pageSize, topology);
}

}  // namespace isoatlas::levelset
