// marchingCubesGpu: marching cubes (marching_cubes.h) on the GPU, the twin of marchingCubesCpu, in GL 4.5 compute shaders
// (extract/shaders/): classify the cells of the visited blocks (triangle and centre counts, the grid
// edges used), compact by prefix sums, make each vertex once on the edge it lies on, then write the
// triangles. It gives the CPU's mesh: the same vertices (positions equal to float rounding) and the
// same triangles, numbered block by block (visited blocks in order, cells and points in each block
// in order) where the CPU numbers them across the whole grid.
// The field is the grid's dense values (uploaded), or, for a Grid whose pagedTexture is set, phi in
// a GPU level set's page pool, read in place through its page table: no dense copy of phi on the host
// or the GPU. Its GPU memory, the field's besides, follows the visited blocks (about 24 bytes per
// visited cell, 64 per vertex (its edge and parameter, and the vertex as drawn) and 12 per triangle), plus two small tables over the grid (4 bytes per
// page and per 8^3 block).
// With no visitBlock, a dense grid's straddling blocks are chosen on the host (straddling_blocks.h);
// a paged grid needs visitBlock.
// Runs in the current GL context (gl::Context::current(), checked); a paged texture must belong to it.
//
// GpuMarchingCubes keeps its buffers from one call to the next (each grown, never shrunk, to what
// the counts of the pass before ask), and leaves the surface in them, for a renderer to draw where
// it lies (render::renderMesh's GpuMeshView); readBack brings it to the host only when asked.
// marchingCubesGpu is one call of a GpuMarchingCubes of its own, read back; it makes no drawn
// vertices (Leave::MeshOnly), whose gradient normals would cost 12 more field reads a vertex.
#pragma once
#include <array>
#include <cstdint>

#include "core/gl/resources.h"
#include "extract/marching_cubes.h"

namespace isoatlas::extract {

// The surface of the last march, in GpuMarchingCubes's buffers (valid until its next march).
struct GpuSurface {
  // Per vertex 32 bytes: its position (vec4: voxel index coordinates, w = 1), then its outward unit
  // normal (vec4: the field's gradient, interpolated along the vertex's edge, in voxel axes, w = 0;
  // a centre vertex's is its ring's mean, normalised).
  unsigned vertexBuffer = 0;  // 0 under Leave::MeshOnly, and with no vertex
  unsigned indexBuffer = 0;  // per triangle its three vertices (u32), counter-clockwise from outside
  std::uint32_t vertexCount = 0, triangleCount = 0;
  Box voxelBox;  // the vertices' bounding box (voxel index coordinates; zero with no drawn vertex)
};

class GpuMarchingCubes {
public:
  enum class Leave {
    DrawnSurface,  // march leaves the GpuSurface to draw, and readBack gives the mesh
    MeshOnly,      // only readBack: march's GpuSurface has no vertex buffer and no box
  };
  explicit GpuMarchingCubes(Leave leave = Leave::DrawnSurface) : leave_(leave) {}
  // The surface {grid = iso} over the blocks visitBlock names; blockSize must be 8.
  GpuSurface march(const Grid& grid, float iso, int blockSize = 8, const VisitBlock& visitBlock = {});
  // The last march's mesh on the host, as marchingCubesGpu returns it (positions made in double from
  // each vertex's grid point and edge parameter, as the CPU makes them).
  MarchingResult readBack() const;
  // The GPU memory these buffers hold (a dense field's copy, and a paged field's pool, not counted).
  std::uint64_t gpuBytes() const;

private:
  gl::Buffer field_, blocks_, slots_, caseIndex_, polygons_, cellTriangles_, cellCentres_, edgeBits_, edgeOffset_,
      visited_, edgeVertices_, vertices_, triangles_, bounds_;
  GpuSurface surface_;
  Leave leave_;
  std::uint32_t edgeVertexCount_ = 0, centreCount_ = 0;
  bool marched_ = false;     // the last march visited blocks and ended
  bool denseField_ = false;  // the last march read a dense field (field_), not a page pool
};

MarchingResult marchingCubesGpu(const Grid& grid, float iso, int blockSize = 8, const VisitBlock& visitBlock = {});

}  // namespace isoatlas::extract
