#include "extract/gpu_marching_cubes.h"

#include <algorithm>

#include "core/error.h"
#include "core/gl/context.h"
#include "core/gl/program.h"
#include "core/gl/resources.h"
#include "extract/gpu_scan.h"

namespace isoatlas::extract {
namespace {

// Mirrors Vertex in shaders/mc_vertices.comp (std430: 32 bytes).
struct GpuVertex {
  std::int32_t point[3];
  float t;
  std::int32_t axis, unused[3];
};
static_assert(sizeof(GpuVertex) == 32);

std::pair<GLuint, GLuint> groupsFor(std::uint64_t n) {
  return {GLuint(std::min<std::uint64_t>(n, 65535)), GLuint((n + 65534) / 65535)};
}

}  // namespace

MarchingResult marchingCubesGpu(const Grid& grid, float iso, int blockSize,
                                const std::function<bool(std::int64_t, std::int64_t, std::int64_t)>& visitBlock) {
  require(blockSize == 8, "the GPU extraction works in blocks of 8^3 cells");
  auto ctx = gl::Context::headless();
  const auto d = grid.dims;
  const std::uint64_t cells = std::uint64_t(d[0] + 1) * std::uint64_t(d[1] + 1) * std::uint64_t(d[2] + 1);
  const std::uint64_t points = std::uint64_t(d[0] + 2) * std::uint64_t(d[1] + 2) * std::uint64_t(d[2] + 2);
  if (points >= (std::uint64_t(1) << 31))
    throw Error("the volume is too large for the GPU extraction path; use --backend cpu", ErrorKind::Failure);

  std::vector<std::int32_t> blocks;
  const std::int64_t nb[3] = {blockCount(d[0], blockSize), blockCount(d[1], blockSize), blockCount(d[2], blockSize)};
  for (std::int64_t bz = 0; bz < nb[2]; ++bz)
    for (std::int64_t by = 0; by < nb[1]; ++by)
      for (std::int64_t bx = 0; bx < nb[0]; ++bx)
        if (!visitBlock || visitBlock(bx, by, bz))
          blocks.insert(blocks.end(), {std::int32_t(bx), std::int32_t(by), std::int32_t(bz), 0});
  MarchingResult result;
  const std::int32_t blockCount = std::int32_t(blocks.size() / 4);
  if (blockCount == 0) return result;

  const gl::Defines defines{{"BLOCK_SIZE", std::to_string(blockSize)}};
  gl::Program classify = gl::Program::compute("extract/shaders/mc_classify.comp", defines);
  gl::Program countEdges = gl::Program::compute("extract/shaders/mc_count_edges.comp");
  gl::Program makeVertices = gl::Program::compute("extract/shaders/mc_vertices.comp", defines);
  gl::Program makeTriangles = gl::Program::compute("extract/shaders/mc_triangles.comp", defines);
  GpuScan scan;

  const PackedCaseTable& table = packedCaseTable();
  gl::Buffer field(grid.voxels() * sizeof(float), grid.values);
  gl::Buffer blockBuffer = gl::Buffer::of(blocks);
  gl::Buffer caseIndex = gl::Buffer::of(table.index), polygons = gl::Buffer::of(table.polygons);
  gl::Buffer cellTriangles(cells * 4), cellCentres(cells * 4), edgeBits(points * 4), edgeOffset(points * 4), visited(16);
  for (gl::Buffer* b : {&cellTriangles, &cellCentres, &edgeBits, &visited}) b->fillZero();

  // The shaders' bindings (marching.glsl and the passes); the scans reuse 0 and 1, so this runs again.
  auto bindAll = [&] {
    int binding = 0;
    for (const gl::Buffer* b : {&field, &blockBuffer, &caseIndex, &polygons, &cellTriangles, &cellCentres, &edgeBits,
                                &visited, &edgeOffset})
      b->bindBase(GL_SHADER_STORAGE_BUFFER, GLuint(binding++));
  };
  bindAll();
  auto common = [&](const gl::Program& p) {
    p.use();
    glUniform3i(p.uniform("dims"), int(d[0]), int(d[1]), int(d[2]));
    glUniform1f(p.uniform("iso"), iso);
    glUniform1i(p.uniform("blockCount"), blockCount);
  };
  const auto [bx, by] = groupsFor(std::uint64_t(blockCount));
  common(classify);
  classify.dispatch(bx, by, 1, GL_SHADER_STORAGE_BARRIER_BIT);

  const auto [px, py] = groupsFor((points + 255) / 256);
  countEdges.use();
  glUniform1ui(countEdges.uniform("pointCount"), GLuint(points));
  countEdges.dispatch(px, py, 1, GL_SHADER_STORAGE_BARRIER_BIT);

  const std::uint32_t triangleCount = scan.exclusive(cellTriangles, std::uint32_t(cells));
  const std::uint32_t centreCount = scan.exclusive(cellCentres, std::uint32_t(cells));
  const std::uint32_t edgeVertexCount = scan.exclusive(edgeOffset, std::uint32_t(points));

  gl::Buffer vertices(std::size_t(std::max<std::uint32_t>(edgeVertexCount, 1)) * sizeof(GpuVertex));
  gl::Buffer triangles(std::size_t(std::max<std::uint32_t>(triangleCount, 1)) * 12);
  bindAll();
  vertices.bindBase(GL_SHADER_STORAGE_BUFFER, 9);
  triangles.bindBase(GL_SHADER_STORAGE_BUFFER, 10);
  common(makeVertices);
  glUniform1ui(makeVertices.uniform("pointCount"), GLuint(points));
  makeVertices.dispatch(px, py, 1, GL_SHADER_STORAGE_BARRIER_BIT);
  common(makeTriangles);
  glUniform1ui(makeTriangles.uniform("edgeVertexCount"), edgeVertexCount);
  makeTriangles.dispatch(bx, by, 1, GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);

  // Read back: vertices as (grid point, t) made positions in double, as the CPU does; centres as
  // the mean of their ring, which every fan (centre, a, b) lists once as a.
  const auto gpuVertices = vertices.read<GpuVertex>(edgeVertexCount);
  const auto corners = triangles.read<std::uint32_t>(std::size_t(triangleCount) * 3);
  std::uint32_t visitedCells = 0;
  visited.download(&visitedCells, 4);
  result.cellsVisited = visitedCells;
  Mesh& mesh = result.mesh;
  mesh.positions.resize(std::size_t(edgeVertexCount) + centreCount, Vec3{0, 0, 0});
  for (std::uint32_t i = 0; i < edgeVertexCount; ++i) {
    const GpuVertex& v = gpuVertices[i];
    Vec3 p{double(v.point[0]), double(v.point[1]), double(v.point[2])};
    p[v.axis] += double(v.t);
    mesh.positions[i] = p;
  }
  std::vector<std::uint32_t> ring(centreCount, 0);
  for (std::size_t t = 0; t < corners.size(); t += 3) {
    if (corners[t] < edgeVertexCount) continue;
    const std::uint32_t c = corners[t];
    mesh.positions[c] = mesh.positions[c] + mesh.positions[corners[t + 1]];
    ++ring[c - edgeVertexCount];
  }
  for (std::uint32_t c = 0; c < centreCount; ++c)
    mesh.positions[edgeVertexCount + c] = mesh.positions[edgeVertexCount + c] * (1.0 / double(ring[c]));
  mesh.faceVertices = corners;
  mesh.faceOffsets.resize(std::size_t(triangleCount) + 1);
  for (std::uint32_t t = 0; t <= triangleCount; ++t) mesh.faceOffsets[t] = 3 * t;
  gl::checkErrors("GPU marching cubes");
  return result;
}

}  // namespace isoatlas::extract
