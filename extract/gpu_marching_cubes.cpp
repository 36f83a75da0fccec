#include "extract/gpu_marching_cubes.h"

#include "extract/case_table.h"
#include "extract/straddling_blocks.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>
#include <optional>

#include "core/error.h"
#include "core/gl/context.h"
#include "core/gl/program.h"
#include "core/gl/resources.h"
#include "core/gl/gpu_scan.h"
#include "core/gl/stage_profile.h"
#include "kExtractShaders.h"
#include "levelset/paged_phi_gpu.h"

namespace isoatlas::extract {
namespace {

// Mirrors Vertex in shaders/mc_vertices.comp (std430: 32 bytes).
struct GpuVertex {
  std::int32_t point[3];
  float t;
  std::int32_t axis, unused[3];
};
static_assert(sizeof(GpuVertex) == 32);

// The blocks that get storage (see marching.glsl): the visited ones first, then those that only hold
// corners of visited cells (a visited block's upper neighbours); and the table from block to slot.
struct BlockStorage {
  std::vector<std::int32_t> blocks;  // x, y, z, 0 per block
  std::int32_t visited = 0;
  std::array<std::int64_t, 3> grid{};  // blocks per axis in `slots`: the grid points' blocks
  std::vector<std::int32_t> slots;     // per block of `grid`: its index in `blocks`, or -1
  std::int32_t count() const { return std::int32_t(blocks.size() / 4); }
};

BlockStorage blockStorage(const std::array<std::int64_t, 3>& d, int blockSize,
                          const std::function<bool(std::int64_t, std::int64_t, std::int64_t)>& visitBlock) {
  BlockStorage s;
  // Grid points run from -1 to dims: they reach one block past the cells' last on some axes.
  for (int a = 0; a < 3; ++a) s.grid[a] = (d[a] + 1) / blockSize + 1;
  s.slots.assign(std::size_t(s.grid[0] * s.grid[1] * s.grid[2]), -1);
  auto slotOf = [&](std::int64_t x, std::int64_t y, std::int64_t z) -> std::int32_t& {
    return s.slots[std::size_t((z * s.grid[1] + y) * s.grid[0] + x)];
  };
  auto add = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    std::int32_t& slot = slotOf(x, y, z);
    if (slot >= 0) return;
    slot = s.count();
    s.blocks.insert(s.blocks.end(), {std::int32_t(x), std::int32_t(y), std::int32_t(z), 0});
  };
  const std::int64_t nb[3] = {blockCount(d[0], blockSize), blockCount(d[1], blockSize), blockCount(d[2], blockSize)};
  std::vector<std::array<std::int64_t, 3>> visited;
  for (std::int64_t bz = 0; bz < nb[2]; ++bz)
    for (std::int64_t by = 0; by < nb[1]; ++by)
      for (std::int64_t bx = 0; bx < nb[0]; ++bx)
        if (visitBlock(bx, by, bz)) {
          add(bx, by, bz);
          visited.push_back({bx, by, bz});
        }
  s.visited = s.count();
  for (const auto& b : visited)
    for (int k = 1; k < 8; ++k) {
      const std::int64_t x = b[0] + (k & 1), y = b[1] + ((k >> 1) & 1), z = b[2] + ((k >> 2) & 1);
      if (x < s.grid[0] && y < s.grid[1] && z < s.grid[2]) add(x, y, z);
    }
  return s;
}

}  // namespace

GpuSurface GpuMarchingCubes::march(const Grid& grid, float iso, int blockSize, const VisitBlock& visitBlock) {
  require(blockSize == 8, "the GPU extraction works in blocks of 8^3 cells");
  const bool paged = grid.pagedTexture != 0;
  require(paged || grid.values, "marchingCubesGpu: the grid has neither values nor a GPU page pool");
  gl::Context& ctx = gl::Context::current();
  gl::StageProfile profile("extract gpu: marching cubes");  // ISOATLAS_GL_PROFILE=1
  profile.stage("choose blocks (cpu)");
  const auto d = grid.dims;
  require(visitBlock || !paged, "marchingCubesGpu: a paged grid needs the blocks to visit");
  const BlockStorage storage = blockStorage(d, blockSize, visitBlock ? visitBlock : straddlingBlocks(grid, iso, blockSize));
  // Until this march ends, readBack gives nothing (a throw below leaves no earlier surface to read).
  surface_ = {};
  edgeVertexCount_ = centreCount_ = 0;
  marched_ = false;
  if (storage.visited == 0) return surface_;
  const std::uint64_t blockCells = std::uint64_t(blockSize) * std::uint64_t(blockSize) * std::uint64_t(blockSize);
  const std::uint64_t cells = std::uint64_t(storage.visited) * blockCells;
  const std::uint64_t points = std::uint64_t(storage.count()) * blockCells;
  // Counts and indices are 32-bit, and the scans would wrap silently: bound them first. A cell's
  // polygons use at most its 12 edges, so it has at most 12 triangles and 4 centre vertices; a grid
  // point has at most 3 edge vertices.
  if (points >= (std::uint64_t(1) << 31) || 3 * points + 4 * cells >= (std::uint64_t(1) << 32) ||
      36 * cells >= (std::uint64_t(1) << 32))
    throw Error("the surface is too large for the GPU extraction path; use --backend cpu", ErrorKind::Failure);

  profile.stage("programs");
  const bool drawn = leave_ == Leave::DrawnSurface;
  gl::Defines defines{{"BLOCK_SIZE", std::to_string(blockSize)}, {"DRAWN_VERTICES", drawn ? "1" : "0"}};
  if (paged) defines.insert(defines.end(), {{"FIELD_PAGES", "1"}, {"PAGE_SIZE", std::to_string(grid.paged.pages->pageSize())}});
  // Ours and the level set's (paged_phi.glsl), in one table.
  static const std::vector<gl::EmbeddedShader> shaders = gl::joinShaderTables({gl::kExtractShaders, levelset::levelsetShaderFiles()});
  const gl::Program& classify = ctx.compute(shaders.data(), "extract/shaders/mc_classify.comp", defines);
  const gl::Program& countEdges = ctx.compute(shaders.data(), "extract/shaders/mc_count_edges.comp");
  const gl::Program& makeVertices = ctx.compute(shaders.data(), "extract/shaders/mc_vertices.comp", defines);
  const gl::Program& makeTriangles = ctx.compute(shaders.data(), "extract/shaders/mc_triangles.comp", defines);
  gl::GpuScan scan;

  // The field: the dense values, or the page table through which the shaders read the pool.
  profile.stage(paged ? "upload page table" : "upload phi");
  std::optional<levelset::PagedPhiGpu> pagedPhi;
  denseField_ = !paged;
  if (paged) {
    pagedPhi.emplace(*grid.paged.pages, grid.pagedTexture);
    field_ = {};  // a dense copy from an earlier call, no longer read
  } else {
    field_.reserve(grid.voxels() * sizeof(float));
    field_.upload(grid.values, grid.voxels() * sizeof(float));
  }
  profile.stage("upload tables, size and clear buffers");
  if (caseIndex_.id() == 0) {
    const PackedCaseTable& table = packedCaseTable();
    caseIndex_ = gl::Buffer::of(table.index), polygons_ = gl::Buffer::of(table.polygons);
  }
  auto put = [](gl::Buffer& b, const std::vector<std::int32_t>& v) {
    b.reserve(v.size() * 4);
    b.upload(v.data(), v.size() * 4);
  };
  put(blocks_, storage.blocks);
  put(slots_, storage.slots);
  for (gl::Buffer* b : {&cellTriangles_, &cellCentres_}) b->reserve(cells * 4);
  for (gl::Buffer* b : {&edgeBits_, &edgeOffset_}) b->reserve(points * 4);
  visited_.reserve(16);
  bounds_.reserve(32);
  cellTriangles_.fillZero(cells * 4);
  cellCentres_.fillZero(cells * 4);
  edgeBits_.fillZero(points * 4);
  visited_.fillZero(16);
  // The box as the bits of (position + 1), which are never negative, so that uint order is float order.
  const std::uint32_t emptyBox[8] = {~0u, ~0u, ~0u, 0, 0, 0, 0, 0};
  bounds_.upload(emptyBox, sizeof emptyBox);

  // The shaders' bindings (marching.glsl and the passes), in binding order; the scans reuse 0 and 1,
  // so this runs again after them.
  const gl::Buffer* bound[] = {&field_, &blocks_, &caseIndex_, &polygons_, &cellTriangles_, &cellCentres_,
                               &edgeBits_, &visited_, &edgeOffset_};
  auto bindAll = [&] {
    for (GLuint binding = 0; binding < std::size(bound); ++binding) bound[binding]->bindBase(GL_SHADER_STORAGE_BUFFER, binding);
    if (pagedPhi) pagedPhi->bindData();  // the page table at binding 0, in the dense field's place
    slots_.bindBase(GL_SHADER_STORAGE_BUFFER, 11);
  };
  bindAll();
  auto common = [&](const gl::Program& p) {
    p.use();
    glUniform3i(p.uniform("dims"), int(d[0]), int(d[1]), int(d[2]));
    glUniform1f(p.uniform("iso"), iso);
    glUniform1i(p.uniform("visitedBlocks"), storage.visited);
    glUniform3i(p.uniform("blockGrid"), int(storage.grid[0]), int(storage.grid[1]), int(storage.grid[2]));
    if (pagedPhi) pagedPhi->setUniforms(p);
  };
  profile.stage("classify cells");
  const auto [bx, by] = gl::dispatchGrid(std::uint64_t(storage.visited));
  common(classify);
  classify.dispatch(bx, by, 1, GL_SHADER_STORAGE_BARRIER_BIT);

  profile.stage("count edges");
  const auto [px, py] = gl::dispatchGrid((points + 255) / 256);
  countEdges.use();
  glUniform1ui(countEdges.uniform("pointCount"), GLuint(points));
  countEdges.dispatch(px, py, 1, GL_SHADER_STORAGE_BARRIER_BIT);

  profile.stage("scan cell triangles");
  const std::uint32_t triangleCount = scan.exclusive(cellTriangles_, std::uint32_t(cells));
  profile.stage("scan cell centres");
  const std::uint32_t centreCount = scan.exclusive(cellCentres_, std::uint32_t(cells));
  profile.stage("scan edge vertices");
  const std::uint32_t edgeVertexCount = scan.exclusive(edgeOffset_, std::uint32_t(points));

  profile.stage("emit vertices");
  const std::size_t vertexCount = std::size_t(edgeVertexCount) + centreCount;
  edgeVertices_.reserve(std::size_t(edgeVertexCount) * sizeof(GpuVertex));
  if (drawn) vertices_.reserve(vertexCount * 32);
  triangles_.reserve(std::size_t(triangleCount) * 12);
  bindAll();
  edgeVertices_.bindBase(GL_SHADER_STORAGE_BUFFER, 9);
  triangles_.bindBase(GL_SHADER_STORAGE_BUFFER, 10);
  if (drawn) {
    vertices_.bindBase(GL_SHADER_STORAGE_BUFFER, 12);
    bounds_.bindBase(GL_SHADER_STORAGE_BUFFER, 13);
  }
  common(makeVertices);
  glUniform1ui(makeVertices.uniform("pointCount"), GLuint(points));
  makeVertices.dispatch(px, py, 1, GL_SHADER_STORAGE_BARRIER_BIT);
  profile.stage("emit triangles");
  common(makeTriangles);
  glUniform1ui(makeTriangles.uniform("edgeVertexCount"), edgeVertexCount);
  makeTriangles.dispatch(bx, by, 1,
                         GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT | GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT |
                             GL_ELEMENT_ARRAY_BARRIER_BIT);
  std::uint32_t box[8] = {};
  if (drawn) {
    profile.stage("read back the box");
    bounds_.download(box, sizeof box);
  }
  gl::checkErrors("GPU marching cubes");
  profile.end();
  edgeVertexCount_ = edgeVertexCount, centreCount_ = centreCount;
  marched_ = true;
  surface_.indexBuffer = triangles_.id();
  surface_.vertexCount = std::uint32_t(vertexCount);
  surface_.triangleCount = triangleCount;
  if (!drawn || vertexCount == 0) return surface_;  // no drawn vertices, or none at all: no box
  surface_.vertexBuffer = vertices_.id();
  for (int a = 0; a < 3; ++a) {
    float lo, hi;
    std::memcpy(&lo, &box[a], 4);
    std::memcpy(&hi, &box[3 + a], 4);
    surface_.voxelBox.min[a] = double(lo) - 1, surface_.voxelBox.max[a] = double(hi) - 1;
  }
  return surface_;
}

std::uint64_t GpuMarchingCubes::gpuBytes() const {
  std::uint64_t bytes = 0;
  for (const gl::Buffer* b : {&blocks_, &slots_, &caseIndex_, &polygons_, &cellTriangles_, &cellCentres_, &edgeBits_, &edgeOffset_,
                              &visited_, &edgeVertices_, &vertices_, &triangles_, &bounds_})
    bytes += b->bytes();
  return bytes;
}

MarchingResult GpuMarchingCubes::readBack() const {
  MarchingResult result;
  if (!marched_) return result;
  gl::StageProfile profile("extract gpu: marching cubes");
  // Read back: vertices as (grid point, t) made positions in double, as the CPU does; centres as
  // the mean of their ring, which every fan (centre, a, b) lists once as a.
  profile.stage("read back mesh");
  const std::uint32_t edgeVertexCount = edgeVertexCount_, centreCount = centreCount_, triangleCount = surface_.triangleCount;
  const auto gpuVertices = edgeVertices_.read<GpuVertex>(edgeVertexCount);
  auto corners = triangles_.read<std::uint32_t>(std::size_t(triangleCount) * 3);
  std::uint32_t visitedCells = 0;
  visited_.download(&visitedCells, 4);
  result.cellsVisited = visitedCells;
  result.gpuBytes = gpuBytes() + (denseField_ ? field_.bytes() : 0);
  profile.stage("assemble mesh (cpu)");
  Mesh& mesh = result.mesh;
  mesh.positions.resize(std::size_t(edgeVertexCount) + centreCount, Vec3{0, 0, 0});
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, edgeVertexCount), [&](const auto& range) {
    for (std::uint32_t i = range.begin(); i != range.end(); ++i) {
      const GpuVertex& v = gpuVertices[i];
      Vec3 p{double(v.point[0]), double(v.point[1]), double(v.point[2])};
      p[v.axis] += double(v.t);
      mesh.positions[i] = p;
    }
  });
  std::vector<std::uint32_t> ring(centreCount, 0);
  for (std::size_t t = 0; t < corners.size(); t += 3) {
    if (corners[t] < edgeVertexCount) continue;
    const std::uint32_t c = corners[t];
    mesh.positions[c] = mesh.positions[c] + mesh.positions[corners[t + 1]];
    ++ring[c - edgeVertexCount];
  }
  for (std::uint32_t c = 0; c < centreCount; ++c)
    mesh.positions[edgeVertexCount + c] = mesh.positions[edgeVertexCount + c] * (1.0 / double(ring[c]));
  mesh.faceVertices = std::move(corners);
  mesh.faceOffsets.resize(std::size_t(triangleCount) + 1);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, triangleCount + 1), [&](const auto& range) {
    for (std::uint32_t t = range.begin(); t != range.end(); ++t) mesh.faceOffsets[t] = 3 * t;
  });
  gl::checkErrors("reading back the GPU marching cubes' mesh");
  return result;
}

MarchingResult marchingCubesGpu(const Grid& grid, float iso, int blockSize, const VisitBlock& visitBlock) {
  GpuMarchingCubes mc(GpuMarchingCubes::Leave::MeshOnly);
  mc.march(grid, iso, blockSize, visitBlock);
  MarchingResult result = mc.readBack();
  return result;
}

}  // namespace isoatlas::extract
