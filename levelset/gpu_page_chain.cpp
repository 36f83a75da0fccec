#include "levelset/gpu_page_chain.h"

#include <algorithm>

#include "core/error.h"
#include "core/gl/program.h"
#include "kLevelsetShaders.h"

namespace isoatlas::levelset {
namespace {

}  // namespace

bool GpuPageChain::fits(std::uint64_t voxels) {
  GLint64 most = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &most);
  return voxels * sizeof(float) <= std::uint64_t(most) && voxels < (std::uint64_t(1) << 31);
}

GpuPageChain::GpuPageChain(gl::Context& ctx, const gl::Defines& solverDefines, std::array<std::int64_t, 3> pages,
                           std::array<std::int64_t, 3> dims, const VolumeSource& source)
    : ctx_(ctx), pages_(pages), dims_(dims), state_(sizeof(PageState)) {
  gl::Defines defines = solverDefines;
  for (const auto& [name, value] : solverDefines)
    if (name == "PAGE_SIZE") pageSize_ = std::stoi(value);
  defines.push_back({"POOL_PAGES_X", std::to_string(textureSlotsPerRow(pageSize_))});
  defines.push_back({"RING_SIZE", std::to_string(kChainRingSize)});
  defines.push_back({"LOG_SIZE", std::to_string(kChainLogSize)});
  auto program = [&](const char* path) { return &ctx_.compute(gl::kLevelsetShaders, path, defines); };
  request_ = program("levelset/shaders/pages_request.comp");
  release_ = program("levelset/shaders/pages_release.comp");
  plan_ = program("levelset/shaders/pages_plan.comp");
  activate_ = program("levelset/shaders/pages_activate.comp");
  entries_ = program("levelset/shaders/pages_entries.comp");
  end_ = program("levelset/shaders/pages_end.comp");
  const std::size_t virtualPages = std::size_t(pages[0] * pages[1] * pages[2]);
  pageTable_ = gl::Buffer(virtualPages * 4);
  marks_ = gl::Buffer(virtualPages * 12);
  marks_.fillZero();
  newList_ = gl::Buffer(virtualPages * 4);  // a page is listed new at most once an iteration
  const std::size_t sliceVoxels = std::size_t(dims[0] * dims[1]);
  source_ = gl::Buffer(sliceVoxels * std::size_t(dims[2]) * sizeof(float));
  std::vector<float> slice(sliceVoxels);
  for (std::int64_t z = 0; z < dims[2]; ++z) {
    for (std::int64_t y = 0; y < dims[1]; ++y) source.readRow(0, y, z, dims[0], &slice[std::size_t(y * dims[0])]);
    source_.upload(slice.data(), sliceVoxels * sizeof(float), std::size_t(z) * sliceVoxels * sizeof(float));
  }
}

void GpuPageChain::sizeSlots(std::int32_t capacity) {
  if (capacity <= capacity_) return;
  const std::size_t bytes = std::size_t(capacity) * 4;
  for (gl::Buffer* b : {&activeList_, &nextList_, &freeStack_}) b->growTo(bytes);
  capacity_ = capacity;
}

void GpuPageChain::upload(const PageManager& pm) {
  sizeSlots(pm.capacity());
  pageTable_.upload(pm.pageTable().data(), pm.pageTable().size() * 4);
  std::vector<std::int32_t> active(pm.activePages().begin(), pm.activePages().end());
  if (!active.empty()) activeList_.upload(active.data(), active.size() * 4);
  const std::vector<std::int32_t>& free = pm.freeSlots();
  if (!free.empty()) freeStack_.upload(free.data(), free.size() * 4);
  PageState s{};
  s.activeCount = std::int32_t(active.size());
  s.freeTop = std::int32_t(free.size());
  s.epoch = epoch_;
  s.peakActive = s.activeCount;
  const auto grid = [](std::int64_t groups) {
    const auto g = gl::dispatchGrid(std::uint64_t(groups));
    return std::array<std::uint32_t, 3>{g[0], g[1], groups > 0 ? 1u : 0u};
  };
  const auto pageGrid = grid(s.activeCount), threadGrid = grid((s.activeCount + 63) / 64), wordGrid = grid((s.activeCount + 3) / 4);
  std::copy(pageGrid.begin(), pageGrid.end(), s.pageArgs);
  std::copy(threadGrid.begin(), threadGrid.end(), s.threadArgs);
  std::copy(wordGrid.begin(), wordGrid.end(), s.wordArgs);
  state_.upload(&s, sizeof s);
}

void GpuPageChain::pagePasses(const ChainTargets& t, bool evaluateAll, const ChainStop& stop, bool fromPlan) {
  state_.bindBase(GL_SHADER_STORAGE_BUFFER, 5);
  pageTable_.bindBase(GL_SHADER_STORAGE_BUFFER, 6);
  marks_.bindBase(GL_SHADER_STORAGE_BUFFER, 12);
  t.messages.bindBase(GL_SHADER_STORAGE_BUFFER, 2);
  activeList_.bindBase(GL_SHADER_STORAGE_BUFFER, 7);
  nextList_.bindBase(GL_SHADER_STORAGE_BUFFER, 8);
  newList_.bindBase(GL_SHADER_STORAGE_BUFFER, 9);
  freeStack_.bindBase(GL_SHADER_STORAGE_BUFFER, 10);
  source_.bindBase(GL_SHADER_STORAGE_BUFFER, 13);
  const GLuint state = state_.id();
  const GLintptr threadArgs = offsetof(PageState, threadArgs),
                 newArgs = offsetof(PageState, newArgs), wordArgs = offsetof(PageState, wordArgs);
  const auto common = [&](const gl::Program& p) {
    p.use();
    glUniform3i(p.uniform("virtualPages"), int(pages_[0]), int(pages_[1]), int(pages_[2]));
  };
  if (!fromPlan) {
    common(*request_);
    glUniform1i(request_->uniform("movedOffset"), t.movedOffset);
    request_->dispatchIndirect(state, threadArgs);
    common(*release_);
    release_->dispatchIndirect(state, threadArgs);
  }
  common(*plan_);
  plan_->dispatch(1);
  common(*activate_);
  glUniform3i(activate_->uniform("dims"), int(dims_[0]), int(dims_[1]), int(dims_[2]));
  glBindImageTexture(0, t.phi, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  glBindImageTexture(2, t.sourcePool, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
  activate_->dispatchIndirect(state, newArgs);
  t.entries.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
  t.evaluate.bindBase(GL_SHADER_STORAGE_BUFFER, 3);
  common(*entries_);
  glUniform1i(entries_->uniform("evaluateAll"), evaluateAll ? 1 : 0);
  entries_->dispatchIndirect(state, wordArgs);
  common(*end_);
  glUniform1i(end_->uniform("window"), stop.window);
  glUniform1i(end_->uniform("untilConverged"), stop.untilConverged ? 1 : 0);
  glUniform1i(end_->uniform("pageArea"), pageSize_ * pageSize_);
  glUniform1d(end_->uniform("changedVoxels"), stop.changedVoxels);
  glUniform1d(end_->uniform("changedShare"), stop.changedShare);
  end_->dispatch(1);
}

PageState GpuPageChain::readState() {
  PageState s;
  state_.download(&s, sizeof s);
  epoch_ = s.epoch;  // the marks hold epochs up to this one, whatever the caller does next
  return s;
}

std::uint64_t GpuPageChain::bytes() const {
  std::uint64_t sum = 0;
  for (const gl::Buffer* b : {&state_, &pageTable_, &marks_, &activeList_, &nextList_, &newList_, &freeStack_, &source_}) sum += b->bytes();
  return sum;
}

void GpuPageChain::grow(std::int32_t oldCapacity, std::int32_t capacity, const PageState& state) {
  sizeSlots(capacity);
  std::vector<std::int32_t> added;
  for (std::int32_t s = capacity - 1; s >= oldCapacity; --s) added.push_back(s);
  freeStack_.upload(added.data(), added.size() * 4, std::size_t(state.freeTop) * 4);
  const std::int32_t header[2] = {state.freeTop + std::int32_t(added.size()), 0};  // freeTop, then the stall: 0
  state_.upload(&header[0], 4, offsetof(PageState, freeTop));
  state_.upload(&header[1], 4, offsetof(PageState, stalled));
}

void GpuPageChain::download(PageManager& pm, std::int32_t capacity, std::int64_t growths) {
  const PageState s = readState();
  const std::size_t virtualPages = pm.pageTable().size();
  std::vector<std::int32_t> table(virtualPages), active(std::size_t(s.activeCount)), free(std::size_t(s.freeTop));
  pageTable_.download(table.data(), table.size() * 4);
  if (!active.empty()) activeList_.download(active.data(), active.size() * 4);
  if (!free.empty()) freeStack_.download(free.data(), free.size() * 4);
  pm.adopt(std::move(table), std::vector<std::int64_t>(active.begin(), active.end()), std::move(free), capacity,
           {.peakActive = s.peakActive, .activations = s.activations, .releases = s.releases, .growths = growths});
}

}  // namespace isoatlas::levelset
