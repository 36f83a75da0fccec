#include "edit/dvt/gpu_tree_passes.h"

#include <algorithm>
#include <cstddef>

#include "core/error.h"
#include "core/gl/gpu_scan.h"
#include "core/gl/program.h"
#include "core/gl/resources.h"
#include "core/gl/stage_profile.h"
#include "kDvtShaders.h"

namespace isoatlas::edit::dvt {
namespace {

constexpr GLuint kGroup = 64;
constexpr GLbitfield kBarrier = GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT;
// After a step that sizes the next dispatches.
constexpr GLbitfield kStepBarrier = kBarrier | GL_COMMAND_BARRIER_BIT;

// The passes' state, the twin of tree_rules.glsl's State (whose comment says what each word is).
struct State {
  std::uint32_t counter, reduces, grown, grownWrapped;
  std::uint32_t nodes, running, restructures, stopped;
  std::uint32_t capacity, nodeLimit, inputCount, needed;
  std::uint32_t remapScanCount, removalScanCount, unused0, unused1;
  std::uint32_t nodeGroups[4], inputGroups[4];
};
static_assert(sizeof(State) == 96, "State must match tree_rules.glsl");
constexpr std::uint32_t kStopCapacity = 1, kStopLimit = 2;
// A chain's iterations before the host looks: a write's expansions grow kExpandLevels levels an
// iteration, so a write whose deepest voxel is at depth d ends within ceil(d / kExpandLevels)
// restructures and one mark that finds nothing left.
int chainIterationsFor(std::uint32_t deepestVoxel) { return int((deepestVoxel + kExpandLevels - 1) / kExpandLevels) + 1; }
// A collapse joins one level of siblings an iteration: a batch of this many between reads.
constexpr int kCollapseIterations = 8;

gl::Defines withRules(gl::Defines extra) {
  gl::Defines d = ruleDefines();
  d.insert(d.end(), extra.begin(), extra.end());
  return d;
}

class GpuTreePasses final : public TreePasses {
public:
  explicit GpuTreePasses(gl::Context& context)
      : markInput_(context.compute(gl::kDvtShaders, "edit/dvt/shaders/dvt_mark.comp", withRules({{"MARK_INPUT", "1"}}))),
        markCollapse_(context.compute(gl::kDvtShaders, "edit/dvt/shaders/dvt_mark.comp", withRules({}))),
        runs_(context.compute(gl::kDvtShaders, "edit/dvt/shaders/dvt_runs.comp", withRules({}))),
        plan_(context.compute(gl::kDvtShaders, "edit/dvt/shaders/dvt_plan.comp", withRules({}))),
        restructure_(context.compute(gl::kDvtShaders, "edit/dvt/shaders/dvt_restructure.comp", withRules({}))),
        begin_(chainStep(context, "BEGIN")),
        clear_(chainStep(context, "CLEAR")),
        gateMark_(chainStep(context, "GATE_MARK")),
        gatePlan_(chainStep(context, "GATE_PLAN")),
        end_(chainStep(context, "END")),
        state_(sizeof(State)) {}

  std::string name() const override { return "gpu"; }

  void load(const VolumeTree& tree) override {
    require(tree.nodeCount() <= kMaxTreeNodes, "the tree has " + std::to_string(tree.nodeCount()) + " nodes, more than a tree can index");
    frame_ = tree.frame;
    scales_ = childScales(frame_);
    count_ = tree.nodeCount();
    capacity_ = std::max<std::uint64_t>(count_, 1024);
    pointers_ = gl::Buffer(capacity_ * sizeof(Pointer));
    cells_ = gl::Buffer(capacity_ * 8);
    pointers_.upload(tree.pointers.data(), count_ * sizeof(Pointer));
    cells_.upload(tree.cells.data(), count_ * 8);
    perNodeFor(capacity_);
    spareCapacity_ = 0;
    setNodes();
  }

  VolumeTree download() const override {
    profile_.stage("download tree");
    VolumeTree t;
    t.frame = frame_;
    t.pointers = pointers_.read<Pointer>(count_);
    t.cells = cells_.read<std::uint32_t>(2 * count_);
    profile_.end();
    return t;
  }

  std::uint64_t nodeCount() const override { return count_; }
  GpuTreeBuffers buffers() const { return {pointers_.id(), cells_.id()}; }

  std::uint64_t bytes() const override {
    return pointers_.bytes() + cells_.bytes() + spare_.bytes() + spareCells_.bytes() + marks_.bytes() + remap_.bytes() +
           removals_.bytes() + expansions_.bytes() + input_.bytes() + hits_.bytes() + state_.bytes();
  }

  void setInput(std::vector<InputVoxel> input) override {
    // A write starts here: a profiled call is a write with the collapse after it, and the caller's
    // work up to the next write (rasterising the next brush) "outside these stages".
    profile_.endCall();
    collapsing_ = false;
    profile_.stage("upload input");
    require(input.size() <= kMaxTreeNodes, "the write has " + std::to_string(input.size()) + " input voxels, more than the GPU backend counts");
    inputCount_ = input.size();
    if (input_.bytes() < std::max<std::size_t>(inputCount_, 1) * sizeof(InputVoxel)) {
      input_ = gl::Buffer(std::max<std::size_t>(inputCount_, 1) * sizeof(InputVoxel) * 5 / 4);
      hits_ = gl::Buffer(input_.bytes() / sizeof(InputVoxel) * 4);
    }
    if (inputCount_ > 0) input_.upload(input.data(), inputCount_ * sizeof(InputVoxel));
    deepestVoxel_ = 0;
    for (const InputVoxel& v : input) deepestVoxel_ = std::max(deepestVoxel_, v.zd >> 16);
    profile_.end();
  }

  std::uint64_t mark(Op op) override {
    collapsing_ = false;
    clearMarks();
    if (inputCount_ == 0) {
      profile_.end();
      return 0;
    }
    bindStreams();
    markInput_.use();
    op_ = op;
    glUniform1ui(markInput_.uniform("op"), std::uint32_t(op));
    const std::uint64_t marks = run(markInput_, inputCount_, "mark");
    // The reduced subtrees' ranges summed before each node: > 0 below a reduced node (the plan
    // removes those whole). Signed sums in unsigned words come out right: every prefix is >= 0.
    if (reduces_ > 0) {
      profile_.stage("scan removals");
      scan_.exclusive(removals_, std::uint32_t(count_ + 1));
    }
    profile_.end();
    return marks;
  }

  std::uint64_t markCollapse() override {
    collapsing_ = true;
    clearMarks();
    inputCount_ = 0;  // no voxel expands anything in a collapse (setInput brings them back)
    bindStreams();
    markCollapse_.use();
    const std::uint64_t marks = run(markCollapse_, count_, "collapse: mark");
    profile_.end();
    return marks;
  }

  Plan plan(bool allowExpand) override {
    bindStreams();
    stage("clear expansions", "collapse: clear expansions");
    expansions_.fillZero(count_ * 16);  // the nodes there are: a clear costs its bytes on a GPU
    if (inputCount_ > 0) {
      runs_.use();
      setExpansionUniforms(runs_);
      run(runs_, inputCount_, "expansion runs");
    }
    const std::uint32_t zero = 0;  // remap[count]: the scan leaves the total there
    remap_.upload(&zero, 4, count_ * 4);
    plan_.use();
    glUniform1ui(plan_.uniform("allowExpand"), allowExpand);
    Plan p;
    p.changes = run(plan_, count_, collapsing_ ? "collapse: plan" : "plan");
    stage("scan remap", "collapse: scan remap");
    p.nodes = scan_.exclusive(remap_, std::uint32_t(count_ + 1));
    // The scan's total is 32-bit: past kMaxTreeNodes, give the bound (over any node limit) instead.
    if (grownWrapped_ || count_ + grown_ > kMaxTreeNodes) p.nodes = grownWrapped_ ? ~std::uint64_t(0) : count_ + grown_;
    profile_.end();
    return p;
  }

  void restructure(const Plan& plan, bool allowExpand, std::uint64_t nodeLimit) override {
    stage("restructure", "collapse: restructure");
    if (spareCapacity_ < plan.nodes) {
      profile_.stage("allocate streams");
      spareCapacity_ = std::min<std::uint64_t>(std::max<std::uint64_t>(plan.nodes, 2 * spareCapacity_), std::max(nodeLimit, plan.nodes));
      spare_ = gl::Buffer(spareCapacity_ * sizeof(Pointer));
      spareCells_ = gl::Buffer(spareCapacity_ * 8);
      stage("restructure", "collapse: restructure");
    }
    bindStreams();
    spare_.bindBase(GL_SHADER_STORAGE_BUFFER, 6);
    spareCells_.bindBase(GL_SHADER_STORAGE_BUFFER, 7);
    restructure_.use();
    glUniform1ui(restructure_.uniform("allowExpand"), allowExpand);
    setExpansionUniforms(restructure_);
    dispatch(restructure_, count_);
    std::swap(pointers_, spare_);
    std::swap(cells_, spareCells_);
    std::swap(capacity_, spareCapacity_);
    count_ = plan.nodes;
    setNodes();
    if (marks_.bytes() < capacity_ * 4) {
      profile_.stage("allocate streams");
      perNodeFor(capacity_);
    }
    profile_.end();
  }

  std::optional<ChainRun> writeChained(Op op, std::uint64_t nodeLimit) override {
    collapsing_ = false;
    op_ = op;
    return runChain(nodeLimit, chainIterationsFor(deepestVoxel_));
  }

  std::optional<ChainRun> collapseChained() override {
    collapsing_ = true;
    inputCount_ = 0;  // as markCollapse: no voxel expands anything (setInput brings them back)
    return runChain(count_, kCollapseIterations);  // a collapse only removes nodes: never past its count
  }

private:
  // The chain of a write or (collapsing_) a collapse: `iterations` at a time, the host reading the
  // state after each batch, until it has ended or stopped at the node limit.
  ChainRun runChain(std::uint64_t nodeLimit, int iterations) {
    ChainRun done;
    for (;;) {
      stage("chain: start", "collapse chain: start");
      // Both streams and the per-node buffers hold `capacity` nodes (the spare may be smaller after a
      // load, the per-node buffers after a swap to a larger stream).
      if (spareCapacity_ < capacity_) {
        spareCapacity_ = capacity_;
        spare_ = gl::Buffer(spareCapacity_ * sizeof(Pointer));
        spareCells_ = gl::Buffer(spareCapacity_ * 8);
      }
      if (marks_.bytes() < capacity_ * 4) perNodeFor(capacity_);
      State s{};
      s.nodes = std::uint32_t(count_), s.running = 1, s.capacity = std::uint32_t(capacity_);
      s.nodeLimit = std::uint32_t(std::min(nodeLimit, kMaxTreeNodes)), s.inputCount = std::uint32_t(inputCount_);
      state_.upload(&s, sizeof s);
      setChainUniforms();
      for (int i = 0; i < iterations; ++i) chainIteration(i % 2 == 0);
      stage("chain: read back state", "collapse chain: read back state");
      state_.download(&s, sizeof s);
      profile_.end();
      // Iteration i read the streams of parity i: after an odd number of restructures the spare holds the tree.
      if (s.restructures % 2 == 1) swapStreams();
      count_ = s.nodes;
      done.iterations += int(s.restructures);
      ++done.reads;
      if (s.stopped == kStopLimit) {
        done.finished = false;
        break;
      }
      if (s.stopped == kStopCapacity) grow(s.needed, nodeLimit);
      else if (s.running == 0) break;
      else if (s.restructures == 0)  // a batch that ran on without changing anything: its steps did not run
        throw Error("the GPU tree's chained passes made no progress (the GL device is lost or broken); use --backend cpu",
                    ErrorKind::Failure);
      // Else more to do than a batch (a collapse of a deep tree; a write's grown streams): go on from here.
    }
    setNodes();  // for the passes the host drives (the limit's iterations)
    return done;
  }

  static const gl::Program& chainStep(gl::Context& context, const char* step) {
    return context.compute(gl::kDvtShaders, "edit/dvt/shaders/dvt_chain.comp",
                           withRules({{step, "1"}, {"STOP_CAPACITY", std::to_string(kStopCapacity) + "u"},
                                      {"STOP_LIMIT", std::to_string(kStopLimit) + "u"},
                                      {"MAX_TREE_NODES", std::to_string(kMaxTreeNodes) + "u"}}));
  }
  // The node count the node passes read (State::nodes), for the passes driven from the host.
  void setNodes() {
    const auto nodes = std::uint32_t(count_);
    state_.upload(&nodes, 4, offsetof(State, nodes));
  }
  // The marks, remap, removals and expansions for `capacity` nodes (their contents are cleared before use).
  void perNodeFor(std::uint64_t capacity) {
    marks_ = gl::Buffer(capacity * 4);
    remap_ = gl::Buffer((capacity + 1) * 4);
    removals_ = gl::Buffer((capacity + 1) * 4);
    expansions_ = gl::Buffer(capacity * 16);
  }
  void swapStreams() {
    std::swap(pointers_, spare_);
    std::swap(cells_, spareCells_);
    std::swap(capacity_, spareCapacity_);
  }
  // Streams for `needed` nodes (doubling, at most the node limit), the tree's kept; per-node buffers to match.
  void grow(std::uint64_t needed, std::uint64_t nodeLimit) {
    profile_.stage("allocate streams");
    const std::uint64_t capacity = std::min(std::max(needed, 2 * capacity_), std::max(nodeLimit, needed));
    gl::Buffer pointers(capacity * sizeof(Pointer)), cells(capacity * 8);
    glCopyNamedBufferSubData(pointers_.id(), pointers.id(), 0, 0, GLsizeiptr(count_ * sizeof(Pointer)));
    glCopyNamedBufferSubData(cells_.id(), cells.id(), 0, 0, GLsizeiptr(count_ * 8));
    pointers_ = std::move(pointers), cells_ = std::move(cells);
    spare_ = gl::Buffer(capacity * sizeof(Pointer)), spareCells_ = gl::Buffer(capacity * 8);
    capacity_ = spareCapacity_ = capacity;
    perNodeFor(capacity_);
    profile_.end();
  }
  void setChainUniforms() {
    const bool expand = !collapsing_;
    markInput_.use();
    glUniform1ui(markInput_.uniform("op"), std::uint32_t(op_));
    glUniform1ui(markInput_.uniform("count"), std::uint32_t(inputCount_));
    runs_.use();
    setExpansionUniforms(runs_);
    glUniform1ui(runs_.uniform("count"), std::uint32_t(inputCount_));
    plan_.use();
    glUniform1ui(plan_.uniform("allowExpand"), expand);
    restructure_.use();
    glUniform1ui(restructure_.uniform("allowExpand"), expand);
    setExpansionUniforms(restructure_);
  }
  // One iteration of a write (mark, plan, restructure) or of a collapse (markCollapse per node, no
  // expansions) with the steps of dvt_chain.comp between, on the streams of one parity (`even`:
  // pointers_ and cells_) into the other's. Reads nothing back.
  void chainIteration(bool even) {
    gl::Buffer &from = even ? pointers_ : spare_, &fromCells = even ? cells_ : spareCells_;
    gl::Buffer &to = even ? spare_ : pointers_, &toCells = even ? spareCells_ : cells_;
    const auto bind = [&] {
      bindStreams(from, fromCells);
      to.bindBase(GL_SHADER_STORAGE_BUFFER, 6);
      toCells.bindBase(GL_SHADER_STORAGE_BUFFER, 7);
    };
    const auto overNodes = [&](const gl::Program& p) { p.dispatchIndirect(state_.id(), offsetof(State, nodeGroups), kBarrier); };
    const auto overInput = [&](const gl::Program& p) { p.dispatchIndirect(state_.id(), offsetof(State, inputGroups), kBarrier); };
    const auto step = [&](const gl::Program& p) { p.dispatch(1, 1, 1, kStepBarrier); };
    const auto maxScan = std::uint32_t(capacity_ + 1);
    bind();
    stage("chain: begin, clear", "collapse chain: begin, clear");
    step(begin_);
    overNodes(clear_);
    stage("chain: mark", "collapse chain: mark");
    if (collapsing_) overNodes(markCollapse_);
    else overInput(markInput_);
    step(gateMark_);
    if (!collapsing_) {  // a collapse reduces nothing and has no input
      profile_.stage("chain: scan removals");
      scan_.exclusive(removals_, state_, offsetof(State, removalScanCount) / 4, maxScan);
      bind();
      profile_.stage("chain: expansion runs");
      overInput(runs_);
    }
    stage("chain: plan", "collapse chain: plan");
    overNodes(plan_);
    stage("chain: scan remap", "collapse chain: scan remap");
    scan_.exclusive(remap_, state_, offsetof(State, remapScanCount) / 4, maxScan);
    bind();
    step(gatePlan_);
    stage("chain: restructure", "collapse chain: restructure");
    overNodes(restructure_);
    step(end_);
    profile_.end();
  }
  void bindStreams() { bindStreams(pointers_, cells_); }
  void bindStreams(const gl::Buffer& pointers, const gl::Buffer& cells) {
    pointers.bindBase(GL_SHADER_STORAGE_BUFFER, 0);
    cells.bindBase(GL_SHADER_STORAGE_BUFFER, 1);
    marks_.bindBase(GL_SHADER_STORAGE_BUFFER, 2);
    remap_.bindBase(GL_SHADER_STORAGE_BUFFER, 3);
    removals_.bindBase(GL_SHADER_STORAGE_BUFFER, 4);
    if (input_.bytes() > 0) input_.bindBase(GL_SHADER_STORAGE_BUFFER, 8), hits_.bindBase(GL_SHADER_STORAGE_BUFFER, 9);
    expansions_.bindBase(GL_SHADER_STORAGE_BUFFER, 10);
    state_.bindBase(GL_SHADER_STORAGE_BUFFER, 5);
  }
  // The write's op and the child scales, for expansionCut (tree_rules.glsl).
  void setExpansionUniforms(const gl::Program& program) const {
    glUniform1ui(program.uniform("op"), std::uint32_t(op_));
    glUniform1fv(program.uniform("childScales"), GLsizei(scales_.size()), scales_.data());
  }
  // A profiled stage, named apart in a collapse.
  void stage(const char* inWrite, const char* inCollapse) const { profile_.stage(collapsing_ ? inCollapse : inWrite); }
  void clearMarks() {
    stage("clear marks", "collapse: clear marks");
    marks_.fillZero(count_ * 4);
    remap_.fillZero((count_ + 1) * 4);
    removals_.fillZero((count_ + 1) * 4);
  }
  static void dispatch(const gl::Program& program, std::uint64_t threads) {
    if (threads == 0) return;
    const auto [gx, gy] = gl::dispatchGrid((threads + kGroup - 1) / kGroup);
    program.dispatch(gx, gy, 1, kBarrier);
  }
  // Runs `program` over `threads` threads with the counters zeroed; returns the first (the others,
  // the reduce marks and the plan's grown nodes, are kept in reduces_, grown_ and grownWrapped_).
  // `stage`: its name for the profile.
  std::uint64_t run(const gl::Program& program, std::uint64_t threads, const char* stage) {
    profile_.stage(stage);
    const std::uint32_t zero[4] = {0, 0, 0, 0};
    state_.upload(zero, 16);
    glUniform1ui(program.uniform("count"), std::uint32_t(threads));
    dispatch(program, threads);
    profile_.stage("read back pass counter");
    std::uint32_t n[4] = {0, 0, 0, 0};
    state_.download(n, 16);
    reduces_ = n[1], grown_ = n[2], grownWrapped_ = n[3] != 0;
    return n[0];
  }

  const gl::Program &markInput_, &markCollapse_, &runs_, &plan_, &restructure_;
  const gl::Program &begin_, &clear_, &gateMark_, &gatePlan_, &end_;  // a chained write's steps
  gl::GpuScan scan_;
  TreeFrame frame_;
  std::vector<float> scales_;
  Op op_ = Op::Union;  // the last mark's
  std::uint64_t count_ = 0, capacity_ = 0, spareCapacity_ = 0, inputCount_ = 0, reduces_ = 0, grown_ = 0;
  std::uint32_t deepestVoxel_ = 0;  // of the input
  bool grownWrapped_ = false;
  gl::Buffer pointers_, cells_, spare_, spareCells_, marks_, remap_, removals_, expansions_, input_, hits_;
  gl::Buffer state_;  // State: the passes' counters, the node count, a chained write's steps
  bool collapsing_ = false;  // since markCollapse, until the next write's mark: names the stages
  // ISOATLAS_GL_PROFILE=1: stage times per write (its collapse included), means over 20 writes.
  // Last: destroyed first, while the context is still current.
  mutable gl::StageProfile profile_{"dvt gpu write", 20};
};

}  // namespace

std::unique_ptr<TreePasses> makeGpuTreePasses() { return std::make_unique<GpuTreePasses>(gl::Context::current()); }

const gl::EmbeddedShader* treeShaderFiles() { return gl::kDvtShaders; }

GpuTreeBuffers gpuTreeBuffers(const TreePasses& passes) {
  const auto* gpu = dynamic_cast<const GpuTreePasses*>(&passes);
  require(gpu != nullptr, "the tree is not on the GPU");
  return gpu->buffers();
}

}  // namespace isoatlas::edit::dvt
