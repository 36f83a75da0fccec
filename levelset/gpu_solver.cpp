#include "levelset/gpu_solver.h"

#include <cstddef>
#include <cstring>
#include <memory>
#include <optional>

#include "core/error.h"
#include "core/gl/context.h"
#include "core/gl/program.h"
#include "core/gl/resources.h"
#include "core/gl/stage_profile.h"
#include "kLevelsetShaders.h"
#include "levelset/gpu_page_chain.h"
#include "levelset/simple_point.h"
#include "levelset/speed.h"

namespace isoatlas::levelset {
namespace {

// Mirrors PageEntry in shaders/pages.glsl (std430: 16 + 27 * 8 bytes, padded to 240).
struct PageEntry {
  std::int32_t info[4];
  std::int32_t origins[27][2];
  std::int32_t pad[2];
};
static_assert(sizeof(PageEntry) == 240);

using Origin = std::array<std::int32_t, 2>;  // std430 ivec2


class GpuSolver final : public SolverBackend {
public:
  GpuSolver(std::shared_ptr<const VolumeSource> source, Topology topology)
      : ctx_(gl::Context::current()), source_(std::move(source)), dims_(source_->geometry().dims), topology_(topology), counters_(16) {}

  std::string name() const override { return "gpu (" + ctx_.info().renderer + ")"; }

  void pagesChanged(const PageManager& pm, const std::vector<std::pair<std::int32_t, float>>& filled) override {
    requireCurrent();
    if (P_ != pm.pageSize()) {
      P_ = pm.pageSize();
      gl::Defines defines{{"PAGE_SIZE", std::to_string(P_)},
                          {"CLAMP", gl::glslFloat(kClamp)},
                          {"CFL_FRACTION", gl::glslFloat(kCflFraction)},
                          {"CURVATURE_LIMIT", gl::glslFloat(kCurvatureLimit)},
                          {"RESCALE_SPEED", gl::glslFloat(kRescaleSpeed)},
                          {"PRESERVE_TOPOLOGY", topology_ == Topology::Preserve ? "1" : "0"},
                          {"HELD_OFF_FRONT", gl::glslFloat(kHeldOffFront)}};
      for (const auto& d : simplePointDefines()) defines.push_back(d);
      defines_ = defines;
      hostDriven_ = passes(defines, false);
      writePages_ = &ctx_.compute(gl::kLevelsetShaders, "levelset/shaders/write_pages.comp", defines);
    }
    profile_.stage("pages changed: grow pool");
    growPool(pm.poolPagesX(), pm.capacity());
    profile_.stage("pages changed: fill new pages");
    if (!filled.empty()) {
      std::vector<std::pair<Origin, float>> fills;
      for (const auto& [slot, value] : filled) fills.push_back({pm.slotOrigin(slot), value});
      fillPages(phi_[current_], fills);
    }
    const auto& active = pm.activePages();
    profile_.stage("pages changed: upload source pages");
    uploadSourcePages(pm);
    profile_.stage("pages changed: page table (cpu)");
    std::vector<PageEntry> entries(std::max<std::size_t>(active.size(), 1));
    for (std::size_t i = 0; i < active.size(); ++i) {
      PageEntry& e = entries[i];
      const auto c = pm.pageCoords(active[i]);
      e = {{pm.slotOf(active[i]), std::int32_t(c[0]), std::int32_t(c[1]), std::int32_t(c[2])}, {}, {0, 0}};
      const auto slots = pm.neighbourSlots(active[i]);
      for (int n = 0; n < 27; ++n) {
        const auto o = pm.slotOrigin(slots[std::size_t(n)]);
        e.origins[n][0] = o[0];
        e.origins[n][1] = o[1];
      }
    }
    pageCount_ = std::int32_t(active.size());
    if (entries.size() * sizeof(PageEntry) > pageTable_.bytes()) {
      pageTable_ = gl::Buffer(entries.size() * sizeof(PageEntry) * 2);
      // Room for twice the pages: the messages' bytes, then the moved bytes after them.
      messages_ = gl::Buffer((entries.size() * 2 + 3) / 4 * 8 + 16);
      evaluate_ = gl::Buffer((entries.size() * 2 + 3) / 4 * 4 + 16);
    }
    profile_.stage("pages changed: upload page table");
    pageTable_.upload(entries.data(), entries.size() * sizeof(PageEntry));
    profile_.end();
  }

  IterationResult iterate(const PageManager&, const SpeedParams& params, const std::vector<std::uint8_t>& evaluate,
                          float settledChange) override {
    requireCurrent();
    IterationResult result;
    // A call is an iteration with what follows it: the page manager's work ("outside these stages")
    // and the pages it changed.
    profile_.endCall();
    if (pageCount_ == 0) return result;
    profile_.stage("clear counters and messages");
    const std::uint32_t zeros[4] = {0, 0, 0, 0};
    counters_.upload(zeros, sizeof zeros);
    const std::size_t messageBytes = (std::size_t(pageCount_) + 3) / 4 * 4;  // a byte per active page
    messages_.fillZero(2 * messageBytes);  // the messages, then the moved bytes
    evaluate_.upload(evaluate.data(), evaluate.size());  // the last word's bytes past the pages are never read
    solverPasses(hostDriven_, params, settledChange, int(messageBytes / 4));
    current_ = 1 - current_;

    // The only read back: 16 bytes of counters and two bytes per active page.
    profile_.stage("read back counters and messages");
    std::uint32_t counters[4];
    counters_.download(counters, sizeof counters);
    std::vector<std::uint8_t> bytes(2 * messageBytes);
    messages_.download(bytes.data(), bytes.size());
    result.messages.assign(bytes.begin(), bytes.begin() + pageCount_);
    result.moved.assign(bytes.begin() + std::ptrdiff_t(messageBytes), bytes.begin() + std::ptrdiff_t(messageBytes) + pageCount_);
    std::memcpy(&result.maxSpeed, &counters[0], 4);
    result.signChanges = std::int32_t(counters[1]);
    std::memcpy(&result.dt, &counters[2], 4);
    result.bytesReadBack = sizeof counters + bytes.size();
    profile_.end();
    return result;
  }

  std::optional<DeviceRun> runOnDevice(PageManager& pm, const SpeedParams& params, const std::vector<std::uint8_t>& evaluate,
                                       float settledChange, const DeviceRunRequest& request) override {
    requireCurrent();
    if (request.window < 1 || request.window > kChainRingSize || P_ == 0) return std::nullopt;
    if (!chain_) {
      const std::size_t voxels = std::size_t(dims_[0] * dims_[1] * dims_[2]);
      if (!GpuPageChain::fits(voxels)) return std::nullopt;
      // The chain activates pages on its own: it holds the whole source, on the GPU.
      chain_ = std::make_unique<GpuPageChain>(ctx_, defines_, pm.pages(), dims_, *source_);
      onDevice_ = passes(defines_, true);
    }
    DeviceRun run;
    std::int32_t capacity = pm.capacity();
    std::int64_t growths = 0;
    startChain(pm, evaluate);
    const ChainStop stop{request.untilConverged, request.window, double(request.changedVoxels), request.changedShare};
    auto targets = [&] {
      return ChainTargets{phi_[current_].id(), sourcePool_.id(), pageTable_, messages_, evaluate_, movedOffsetOnDevice(capacity)};
    };
    const bool evaluateAll = !(settledChange > 0);
    // Each iteration writes the other phi copy; iterations queued past a stop or a stall do nothing,
    // so which copy is current follows the iterations done, not those queued.
    const int firstCurrent = current_;
    bool resumed = false;  // a stalled iteration was finished after the last read
    while (true) {
      const int n = std::min(kChainIterations, request.maxIterations - run.iterations - (resumed ? 1 : 0));
      for (int i = 0; i < n; ++i) {
        profile_.stage("clear messages");
        messages_.fillZero();
        solverPasses(onDevice_, params, settledChange, movedOffsetOnDevice(capacity));
        current_ = 1 - current_;  // solverPasses wrote the other copy
        profile_.stage("page passes (on the device)");
        chain_->pagePasses(targets(), evaluateAll, stop);
        profile_.endCall();  // with profiling on, stage times are means per iteration
      }
      if (n <= 0 && !resumed) break;
      profile_.stage("read back the page state");
      const PageState state = chain_->readState();
      profile_.end();
      logIterations(state, request, run);
      current_ = firstCurrent ^ (run.iterations & 1);
      resumed = false;
      if (state.stopped) {
        run.converged = true;
        break;
      }
      if (state.stalled) {  // more new pages than free slots: grow the pool, then finish the iteration
        std::int32_t grownTo = capacity;
        while (state.freeTop + (grownTo - capacity) < state.newCount) grownTo = pm.grownCapacity(grownTo), ++growths;  // as PageManager counts them
        growPool(pm.poolPagesX(), grownTo);
        sizeForChain(grownTo);
        chain_->grow(capacity, grownTo, state);
        capacity = grownTo;
        current_ = firstCurrent ^ ((run.iterations + 1) & 1);  // the stalled iteration's phi
        chain_->pagePasses(targets(), evaluateAll, stop, true);
        resumed = true;
        continue;
      }
      if (run.iterations >= request.maxIterations) break;
    }
    finishChain(pm, capacity, growths, run);
    return run;
  }

  std::vector<float> readSlots(const PageManager& pm, const std::vector<std::int32_t>& slots) override {
    requireCurrent();
    const std::size_t area = std::size_t(P_) * std::size_t(P_);
    std::vector<float> out(slots.size() * area);
    if (slots.empty()) return out;
    // Many pages: one read of the whole pool; few: one read per page.
    if (slots.size() > 64) {
      std::vector<float> pool;
      readPool(pool);
      for (std::size_t s = 0; s < slots.size(); ++s) {
        const auto o = pm.slotOrigin(slots[s]);
        for (int y = 0; y < P_; ++y)
          std::memcpy(&out[s * area + std::size_t(y * P_)], &pool[std::size_t(o[1] + y) * std::size_t(poolWidth_) + std::size_t(o[0])],
                      std::size_t(P_) * 4);
      }
    } else {
      glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);  // the image stores of the last step, before the reads
      for (std::size_t s = 0; s < slots.size(); ++s) {
        const auto o = pm.slotOrigin(slots[s]);
        glGetTextureSubImage(phi_[current_].id(), 0, o[0], o[1], 0, P_, P_, 1, GL_RED, GL_FLOAT, GLsizei(area * 4),
                             &out[s * area]);
      }
    }
    gl::checkErrors("reading phi pages");
    return out;
  }

  void writeSlots(const PageManager& pm, const std::vector<std::int32_t>& slots, const std::vector<float>& values) override {
    requireCurrent();
    std::vector<Origin> origins;
    for (std::int32_t slot : slots) origins.push_back(pm.slotOrigin(slot));
    writePages(phi_[current_], origins, values);
  }

  const float* phiPoolOnHost() override {
    requireCurrent();
    readPool(hostPool_);
    return hostPool_.data();
  }

  // Handed out only while the solver's context is current, for work in that context.
  unsigned phiPoolTexture() const override {
    requireCurrent();
    return phi_[current_].id();
  }

  std::uint64_t physicalBytes() const override {
    // GPU memory: four pool textures (phi twice, rate, source) and the tables, following the active
    // pages, and once a run has managed its pages on the GPU, the chain's buffers with the whole source.
    return std::uint64_t(poolWidth_) * std::uint64_t(poolHeight_) * 4 * 4 + pageTable_.bytes() + messages_.bytes() +
           (chain_ ? chain_->bytes() : 0);
  }

private:
  // Every GL call below acts on the current context: it must be the one the solver was made in.
  void requireCurrent() const {
    if (!ctx_.isCurrent())
      throw Error("the GPU level set is used while the GL context it was made in is not current", ErrorKind::Failure);
  }

  // The whole current phi pool into `out`, after the image stores of the last step.
  void readPool(std::vector<float>& out) const {
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
    phi_[current_].readRedFloats(out);
  }

  void setCommon(const gl::Program& p) const {
    p.use();
    glUniform1i(p.uniform("pageCount"), pageCount_);
    glUniform3i(p.uniform("dims"), int(dims_[0]), int(dims_[1]), int(dims_[2]));
  }

  // The solver's passes, driven by the host (pageCount a uniform) or on the device (PAGES_ON_GPU: the
  // count and the grids from the chain's state).
  struct Passes {
    const gl::Program *speed = nullptr, *update = nullptr, *message = nullptr, *topology = nullptr;
    bool onDevice = false;
  };
  Passes passes(gl::Defines defines, bool onDevice) {
    defines.push_back({"PAGES_ON_GPU", onDevice ? "1" : "0"});
    auto program = [&](const char* path) { return &ctx_.compute(gl::kLevelsetShaders, path, defines); };
    Passes p{program("levelset/shaders/speed.comp"), program("levelset/shaders/update.comp"),
             program("levelset/shaders/message.comp"), nullptr, onDevice};
    if (topology_ == Topology::Preserve) p.topology = program("levelset/shaders/topology.comp");
    return p;
  }

  // Speed, update (and the topology's classes) and messages over the active pages, from phi_[current_]
  // into the other copy.
  void solverPasses(const Passes& p, const SpeedParams& params, float settledChange, int movedOffset) {
    pageTable_.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
    counters_.bindBase(GL_SHADER_STORAGE_BUFFER, 1);
    messages_.bindBase(GL_SHADER_STORAGE_BUFFER, 2);
    evaluate_.bindBase(GL_SHADER_STORAGE_BUFFER, 3);
    if (p.onDevice) chain_->state().bindBase(GL_SHADER_STORAGE_BUFFER, 5);
    const std::array<GLuint, 2> grid = gl::dispatchGrid(std::uint64_t(pageCount_));  // no structured binding: clang 14 captures none
    const GLbitfield barrier = GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT;
    auto dispatch = [&](const gl::Program& program, GLbitfield after) {
      if (p.onDevice) program.dispatchIndirect(chain_->state().id(), offsetof(PageState, pageArgs), after | GL_COMMAND_BARRIER_BIT);
      else program.dispatch(grid[0], grid[1], 1, after);
    };
    profile_.stage("speed");
    setCommon(*p.speed);
    glUniform1f(p.speed->uniform("target"), params.target);
    glUniform1f(p.speed->uniform("width"), params.width);
    glUniform1f(p.speed->uniform("alpha"), params.alpha);
    glBindImageTexture(0, phi_[current_].id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
    glBindImageTexture(1, rate_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glBindImageTexture(2, sourcePool_.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
    dispatch(*p.speed, barrier);

    profile_.stage("update");
    setCommon(*p.update);
    glUniform1f(p.update->uniform("alpha"), params.alpha);
    glUniform1f(p.update->uniform("settledChange"), settledChange);
    glUniform1i(p.update->uniform("movedOffset"), movedOffset);
    glBindImageTexture(0, phi_[current_].id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
    const bool preserve = topology_ == Topology::Preserve;
    glBindImageTexture(1, rate_.id(), 0, GL_FALSE, 0, preserve ? GL_READ_WRITE : GL_READ_ONLY, GL_R32F);
    glBindImageTexture(2, phi_[1 - current_].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    dispatch(*p.update, barrier);
    if (preserve) {
      profile_.stage("topology: sides changed where simple");
      setCommon(*p.topology);
      glUniform1f(p.topology->uniform("settledChange"), settledChange);
      glUniform1i(p.topology->uniform("movedOffset"), movedOffset);
      glBindImageTexture(0, phi_[current_].id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
      glBindImageTexture(1, rate_.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
      glBindImageTexture(2, phi_[1 - current_].id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
      for (int parity = 0; parity < 8; ++parity) {  // one class after another: each reads the ones before
        glUniform1i(p.topology->uniform("parity"), parity);
        dispatch(*p.topology, barrier);
      }
    }

    profile_.stage("messages");
    setCommon(*p.message);
    glBindImageTexture(0, phi_[1 - current_].id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32F);
    dispatch(*p.message, GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
  }

  // The page manager's state and the first iteration's evaluate bytes onto the GPU, the counters at 0.
  void startChain(const PageManager& pm, const std::vector<std::uint8_t>& evaluate) {
    sizeForChain(pm.capacity());
    evaluate_.fillZero();
    if (!evaluate.empty()) evaluate_.upload(evaluate.data(), evaluate.size());
    const std::uint32_t zeros[4] = {0, 0, 0, 0};
    counters_.upload(zeros, sizeof zeros);
    chain_->upload(pm);
  }

  // The iterations the state logs since the last read: their time steps, and progress.
  static void logIterations(const PageState& state, const DeviceRunRequest& request, DeviceRun& run) {
    run.bytesReadBack += sizeof(PageState);
    for (int i = run.iterations; i < state.iterations; ++i) {
      const auto& entry = state.log[i % kChainLogSize];
      float dt;
      std::memcpy(&dt, &entry[1], 4);
      run.dt.push_back(dt);
      if (request.progress) request.progress(i + 1, entry[2]);
    }
    run.iterations = state.iterations;
  }

  // The GPU's pages back into pm, and which of them the next iteration evaluates.
  void finishChain(PageManager& pm, std::int32_t capacity, std::int64_t growths, DeviceRun& run) {
    chain_->download(pm, capacity, growths);
    pageCount_ = std::int32_t(pm.activePages().size());
    run.nextEvaluate.resize((std::size_t(pageCount_) + 3) / 4 * 4);
    if (pageCount_ > 0) evaluate_.download(run.nextEvaluate.data(), run.nextEvaluate.size());
    run.nextEvaluate.resize(std::size_t(pageCount_));
    // The chain copied the active pages' intensities into their slots; what the others hold is unknown.
    slotPage_.assign(std::size_t(pm.capacity()), -1);
    for (std::int64_t page : pm.activePages()) slotPage_[std::size_t(pm.slotOf(page))] = page;
    run.bytesReadBack += pm.pageTable().size() * 4 + (pm.activePages().size() + pm.freeSlots().size()) * 4 + run.nextEvaluate.size();
  }

  // On the device, the moved bytes follow room for every slot's message.
  static int movedOffsetOnDevice(std::int32_t capacity) { return (capacity + 3) / 4; }

  // The per-page buffers the chain writes, room for `capacity` pages, keeping what they hold.
  void sizeForChain(std::int32_t capacity) {
    const std::size_t words = std::size_t(movedOffsetOnDevice(capacity));
    pageTable_.growTo(std::size_t(capacity) * sizeof(PageEntry));
    messages_.growTo(2 * words * 4);
    evaluate_.growTo(words * 4);
  }

  // Grows the pool textures to `capacity` slots, keeping what they hold: rows are appended, so every
  // slot keeps its origin. The static pages are written once, into both copies.
  void growPool(std::int32_t poolPagesX, std::int32_t capacity) {
    const int width = poolPagesX * P_, height = capacity / poolPagesX * P_;
    if (height <= poolHeight_) return;
    if (height > ctx_.info().maxTextureSize)
      throw Error("the GPU's physical page pool is full (" + std::to_string(capacity) + " pages); use --backend cpu",
                  ErrorKind::Failure);
    glMemoryBarrier(GL_ALL_BARRIER_BITS);  // image stores before the copies below read the texels
    for (gl::Texture* t : {&phi_[0], &phi_[1], &rate_, &sourcePool_}) {
      gl::Texture grown = gl::Texture::texture2D(GL_R32F, width, height);
      if (poolHeight_ > 0) glCopyImageSubData(t->id(), GL_TEXTURE_2D, 0, 0, 0, 0, grown.id(), GL_TEXTURE_2D, 0, 0, 0, 0, width, poolHeight_, 1);
      *t = std::move(grown);
    }
    if (poolHeight_ == 0) {
      const Origin out{0, 0}, in{P_, 0};  // slots 0 and 1 (PageManager::slotOrigin)
      const std::vector<std::pair<Origin, float>> statics{{out, -kClamp}, {in, kClamp}};
      fillPages(phi_[0], statics);
      fillPages(phi_[1], statics);
    }
    poolWidth_ = width;
    poolHeight_ = height;
    gl::checkErrors("growing the page pool");
  }

  // The source's intensities live in pages too, in the slot beside phi's: each slot holding a page
  // other than the one it last received gets that page's intensities (padding past the volume's edge
  // is 0 and never read). Slots keep their content while a page stays active.
  void uploadSourcePages(const PageManager& pm) {
    slotPage_.resize(std::size_t(pm.capacity()), -1);
    const std::size_t area = std::size_t(P_) * std::size_t(P_);
    std::vector<Origin> origins;
    std::vector<float> values;
    for (std::int64_t page : pm.activePages()) {
      const std::int32_t slot = pm.slotOf(page);
      if (slotPage_[std::size_t(slot)] == page) continue;
      slotPage_[std::size_t(slot)] = page;
      origins.push_back(pm.slotOrigin(slot));
      values.resize(values.size() + area, 0.0f);
      float* out = &values[values.size() - area];
      const auto c = pm.pageCoords(page);
      const std::int64_t x0 = c[0] * P_, n = std::min<std::int64_t>(P_, dims_[0] - x0);
      for (int y = 0; y < P_ && c[1] * P_ + y < dims_[1]; ++y)
        source_->readRow(x0, c[1] * P_ + y, c[2], n, out + y * P_);
    }
    writePages(sourcePool_, origins, values);
  }

  // values: P x P per origin, rows in order; sent in batches of at most 128 MiB, the storage block
  // size every GL 4.5 driver allows.
  void writePages(const gl::Texture& target, const std::vector<Origin>& origins, const std::vector<float>& values) {
    const std::size_t area = std::size_t(P_) * std::size_t(P_);
    const std::size_t batch = (std::size_t(128) << 20) / (area * sizeof(float));
    writePages_->use();
    glBindImageTexture(0, target.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    for (std::size_t first = 0; first < origins.size(); first += batch) {
      const std::size_t n = std::min(batch, origins.size() - first);
      gl::Buffer originBuffer(n * sizeof(Origin), &origins[first]), valueBuffer(n * area * sizeof(float), &values[first * area]);
      originBuffer.bindBase(GL_SHADER_STORAGE_BUFFER, 3);
      valueBuffer.bindBase(GL_SHADER_STORAGE_BUFFER, 4);
      glUniform1i(writePages_->uniform("pageCount"), int(n));
      const auto [x, y] = gl::dispatchGrid(n);
      writePages_->dispatch(x, y, 1, GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    }
    gl::checkErrors("writing pages");
  }

  // Each page filled with one value (a newly activated page starts as the static page it was).
  void fillPages(const gl::Texture& target, const std::vector<std::pair<Origin, float>>& fills) {
    const std::size_t area = std::size_t(P_) * std::size_t(P_);
    std::vector<Origin> origins;
    std::vector<float> values;
    for (const auto& [origin, value] : fills) {
      origins.push_back(origin);
      values.insert(values.end(), area, value);
    }
    writePages(target, origins, values);
  }

  gl::Context& ctx_;
  std::shared_ptr<const VolumeSource> source_;  // read page by page (and whole into chain_'s buffer once made)
  std::array<std::int64_t, 3> dims_;
  Topology topology_;
  std::vector<std::int64_t> slotPage_;  // per slot: the page whose intensities sourcePool_ holds there
  gl::Texture phi_[2], rate_, sourcePool_;
  gl::Buffer pageTable_, counters_, messages_, evaluate_;  // evaluate_: a byte per active page, iterate's
  gl::Defines defines_;  // the shaders' constants, for the chain's programs
  Passes hostDriven_, onDevice_;  // ctx_'s programs
  const gl::Program* writePages_ = nullptr;
  std::unique_ptr<GpuPageChain> chain_;  // made at the first run on the device
  std::vector<float> hostPool_;  // phiPoolOnHost's copy
  int current_ = 0, P_ = 0, poolWidth_ = 0, poolHeight_ = 0;
  std::int32_t pageCount_ = 0;
  // ISOATLAS_GL_PROFILE=1: stage times, means over 100 iterations. Last: destroyed first, while the
  // context is still current.
  gl::StageProfile profile_{"level set gpu iteration", 100};
};

}  // namespace

std::unique_ptr<SolverBackend> makeGpuSolver(std::shared_ptr<const VolumeSource> source, Topology topology) {
  return std::make_unique<GpuSolver>(std::move(source), topology);
}

}  // namespace isoatlas::levelset
