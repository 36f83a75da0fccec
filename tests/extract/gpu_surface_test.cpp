// The GPU's marching cubes kept between calls and left on the GPU (extract/gpu_marching_cubes.h):
// the CPU twin's mesh call after call through the same buffers; the vertices as drawn are the mesh's,
// with outward normals; a level set's surface drawn where it lies is the picture of its mesh read back.
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "core/error.h"
#include "extract/extract_surface.h"
#include "extract/gpu_marching_cubes.h"
#include "extract/marching_cubes.h"
#include "levelset/level_set.h"
#include "render/mesh_render.h"
#include "tests/extract/same_mesh.h"
#include "tests/gl_context.h"
#include "tests/test_util.h"

namespace isoatlas::extract {
namespace {

constexpr double kCentre[3] = {19.3, 17.6, 14.2};

Volume ball(double radius) {
  return test::fieldVolume({40, 36, 30}, [radius](double x, double y, double z) {
    return radius - std::sqrt((x - kCentre[0]) * (x - kCentre[0]) + (y - kCentre[1]) * (y - kCentre[1]) + (z - kCentre[2]) * (z - kCentre[2]));
  });
}

Grid gridOf(const Volume& v) { return Grid{v.dims, reinterpret_cast<const float*>(v.data.data())}; }

struct DrawnVertex {
  float position[4], normal[4];
};

std::vector<DrawnVertex> drawnVertices(const GpuSurface& s) {
  std::vector<DrawnVertex> out(s.vertexCount);
  glGetNamedBufferSubData(s.vertexBuffer, 0, GLsizeiptr(out.size() * sizeof(DrawnVertex)), out.data());
  return out;
}

TEST(GpuMarchingCubes, KeptBuffersGiveTheCpuMeshCallAfterCall) {
  test::glContext();
  const Volume small = ball(4), large = ball(12);
  GpuMarchingCubes mc;
  std::vector<GpuSurface> surfaces;
  std::vector<std::uint64_t> bytes;
  for (const Volume* v : {&small, &large, &small}) {
    surfaces.push_back(mc.march(gridOf(*v), 0.0f));
    bytes.push_back(mc.gpuBytes());
    const MarchingResult back = mc.readBack();
    const MarchingResult cpu = marchingCubes(levelset::Backend::Cpu, gridOf(*v), 0.0f);
    test_mesh::expectSameMesh(cpu.mesh, back.mesh);
    EXPECT_EQ(back.cellsVisited, cpu.cellsVisited);
    EXPECT_EQ(surfaces.back().vertexCount, back.mesh.vertexCount());
    EXPECT_EQ(surfaces.back().triangleCount, back.mesh.faceCount());
  }
  EXPECT_GT(surfaces[1].triangleCount, 4 * surfaces[0].triangleCount);
  EXPECT_GT(bytes[1], bytes[0]) << "the buffers grew for the larger surface";
  // The smaller surface again: drawn from the buffers the larger one grew, none made anew.
  EXPECT_EQ(bytes[2], bytes[1]);
  EXPECT_EQ(surfaces[2].vertexBuffer, surfaces[1].vertexBuffer);
  EXPECT_EQ(surfaces[2].indexBuffer, surfaces[1].indexBuffer);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(surfaces[2].voxelBox.min[k], surfaces[0].voxelBox.min[k]) << "the box is the last march's, not the larger one's before";
    EXPECT_EQ(surfaces[2].voxelBox.max[k], surfaces[0].voxelBox.max[k]);
  }
  // Nothing to march: an empty surface, and the mesh read back empty.
  const Volume outside = ball(-1);
  const GpuSurface none = mc.march(gridOf(outside), 0.0f);
  EXPECT_EQ(none.triangleCount, 0u);
  EXPECT_EQ(none.voxelBox.min, (Vec3{0, 0, 0}));
  EXPECT_EQ(none.voxelBox.max, (Vec3{0, 0, 0}));
  EXPECT_EQ(mc.readBack().mesh.faceCount(), 0u);
}

// A march only to be read back (marchingCubesGpu's) makes no drawn vertices and reads back the same mesh.
TEST(GpuMarchingCubes, AMarchForTheMeshOnlyLeavesNothingToDrawAndTheSameMesh) {
  test::glContext();
  const Volume v = ball(9);
  GpuMarchingCubes drawn, meshOnly(GpuMarchingCubes::Leave::MeshOnly);
  const GpuSurface a = drawn.march(gridOf(v), 0.0f), b = meshOnly.march(gridOf(v), 0.0f);
  EXPECT_NE(a.vertexBuffer, 0u);
  EXPECT_EQ(b.vertexBuffer, 0u);
  EXPECT_EQ(b.voxelBox.max, (Vec3{0, 0, 0}));
  EXPECT_EQ(b.vertexCount, a.vertexCount);
  EXPECT_LT(meshOnly.gpuBytes(), drawn.gpuBytes()) << "no drawn vertices held";
  test_mesh::expectIdenticalMesh(drawn.readBack().mesh, meshOnly.readBack().mesh);
}

TEST(GpuMarchingCubes, DrawnVerticesAreTheMeshsWithOutwardNormalsInTheirBox) {
  test::glContext();
  const Volume v = ball(9);
  GpuMarchingCubes mc;
  const GpuSurface s = mc.march(gridOf(v), 0.0f);
  const Mesh mesh = mc.readBack().mesh;
  const std::vector<DrawnVertex> drawn = drawnVertices(s);
  ASSERT_EQ(drawn.size(), mesh.vertexCount());
  Box box{mesh.positions[0], mesh.positions[0]};
  double worstDegrees = 0;
  for (std::size_t i = 0; i < drawn.size(); ++i) {
    const Vec3& p = mesh.positions[i];
    for (int k = 0; k < 3; ++k) {
      ASSERT_NEAR(drawn[i].position[k], p[k], 1e-5) << "vertex " << i;
      box.min[k] = std::min(box.min[k], p[k]), box.max[k] = std::max(box.max[k], p[k]);
    }
    EXPECT_EQ(drawn[i].position[3], 1.0f);
    const Vec3 n{drawn[i].normal[0], drawn[i].normal[1], drawn[i].normal[2]};
    ASSERT_NEAR(norm(n), 1.0, 1e-5) << "vertex " << i;
    const Vec3 radial = unit(p - Vec3{kCentre[0], kCentre[1], kCentre[2]});  // the sphere's outward normal
    worstDegrees = std::max(worstDegrees, std::acos(std::clamp(dot(n, radial), -1.0, 1.0)) * 180 / M_PI);
  }
  EXPECT_LT(worstDegrees, 3.0);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(s.voxelBox.min[k], box.min[k], 1e-5);
    EXPECT_NEAR(s.voxelBox.max[k], box.max[k], 1e-5);
  }
}

// A level set in a volume that is scaled, turned and mirrored into the world: its surface drawn where
// the GPU left it (placed by the volume's map, normals by its inverse transpose) is the picture of
// the mesh read back and mapped to the world on the host.
TEST(GpuMarchingCubes, ALevelSetsSurfaceDrawnWhereItLiesIsItsMeshsPicture) {
  test::glContext();
  Volume image = test::fieldVolume({48, 40, 28}, [](double x, double y, double z) {
    const double q = std::hypot(x - 23.4, y - 19.2) - 11;
    return std::sqrt(q * q + (z - 13.7) * (z - 13.7)) < 6 ? 100.0 : 20.0;
  });
  image.spacing = {0.8, 1.1, 1.5};
  image.origin = {-12, 30, 4};
  const double c = std::cos(0.5), s = std::sin(0.5);
  image.direction.m = {{{c, -s, 0}, {0, 0, 1}, {s, c, 0}}};  // a turn about z, then y and z swapped: a mirror
  levelset::LevelSet ls(image, {100, 40, 0.8f}, {.backend = levelset::Backend::Gpu, .pageSize = 8});
  ls.addSphere({34.4, 19.2, 13.7}, 3);
  ls.run({.maxIterations = 300});
  GpuMarchingCubes mc;
  const GpuSurface surface = marchLevelSetOnGpu(ls, mc);
  ASSERT_GT(surface.triangleCount, 1000u);
  render::GpuMeshView view{surface.vertexBuffer, surface.indexBuffer, surface.triangleCount};
  render::placeInVolume(view, ls.geometry(), surface.voxelBox);
  const Mesh mesh = extractLevelSet(ls, {.backend = levelset::Backend::Gpu});
  // The placed box holds the mesh as the host maps it (within float rounding); both pictures are then
  // framed on the mesh's own box, as renderMesh frames a mesh on the host.
  const Box world = boundingBox(mesh.positions);
  for (int k = 0; k < 3; ++k) {
    EXPECT_LE(view.box.min[k], world.min[k] + 1e-4);
    EXPECT_GE(view.box.max[k], world.max[k] - 1e-4);
  }
  view.box = world;
  const render::MeshRenderOptions options{.width = 160, .height = 120, .viewDirection = {0.3, 1, -0.4}};
  const Image onGpu = render::renderMesh(view, options);
  const Image readBack = render::renderMesh(mesh, options);
  ASSERT_EQ(onGpu.pixels.size(), readBack.pixels.size());
  std::size_t covered = 0, silhouetteDiffers = 0;
  double difference = 0;
  for (std::size_t p = 0; p < onGpu.pixels.size(); p += 3) {
    const bool a = onGpu.pixels[p] != 255 || onGpu.pixels[p + 1] != 255, b = readBack.pixels[p] != 255 || readBack.pixels[p + 1] != 255;
    covered += a;
    silhouetteDiffers += a != b;
    for (std::size_t k = 0; k < 3; ++k) difference += std::abs(int(onGpu.pixels[p + k]) - int(readBack.pixels[p + k]));
  }
  const double pixels = double(onGpu.pixels.size() / 3);
  EXPECT_GT(double(covered), 0.2 * pixels);
  EXPECT_LT(double(silhouetteDiffers), 0.005 * pixels);
  // Gradient normals against the read-back mesh's area-weighted ones: 7.6 levels of shading apart on
  // the mean (normals taken by the map itself rather than its inverse transpose: 21; untransformed: 116).
  EXPECT_LT(difference / (3 * double(covered)), 12.0);
}

TEST(GpuMarchingCubes, ACpuLevelSetsSurfaceIsNotLeftOnTheGpu) {
  test::glContext();
  const Volume image = ball(6);
  levelset::LevelSet ls(image, {0, 40, 0.8f}, {.backend = levelset::Backend::Cpu});
  ls.addSphere({kCentre[0], kCentre[1], kCentre[2]}, 3);
  GpuMarchingCubes mc;
  EXPECT_THROW(marchLevelSetOnGpu(ls, mc), Error);
}

}  // namespace
}  // namespace isoatlas::extract
