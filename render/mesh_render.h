// renderMesh: a picture of a triangle mesh, lit, framed on its bounding box, seen from a direction,
// drawn offscreen in the current GL context (gl::Context::current(), checked: headless EGL on a GPU or
// Mesa's llvmpipe, or a window's).
//   mesh:      triangles in world coordinates (normals are computed from the faces), or a mesh
//              already in GPU buffers of that context (GpuMeshView: drawn where it lies, no upload)
//   options:   image size, view direction (from the camera into the scene), up vector, colours
// Returns an RGB image, rows top to bottom.
#pragma once
#include <cstdint>

#include "core/image.h"
#include "core/mesh.h"
#include "core/volume.h"

namespace isoatlas::render {

struct MeshRenderOptions {
  int width = 800, height = 600;
  Vec3 viewDirection{0, 1, 0};  // from the camera into the scene (default: from the front, RAS +y)
  Vec3 up{0, 0, 1};
  Vec3 colour{0.93, 0.78, 0.62};
  Vec3 background{1, 1, 1};
};

Image renderMesh(const Mesh& mesh, const MeshRenderOptions& options = {});

// A mesh in GPU buffers: per vertex its position and its normal (vec4 each, 32 bytes), three u32
// corners per triangle; positions reach the world by the affine map toWorld (world = linear * p +
// offset), normals by normalToWorld (linear's inverse transpose, or any positive multiple of it).
struct GpuMeshView {
  unsigned vertexBuffer = 0, indexBuffer = 0;
  std::uint32_t triangleCount = 0;
  Box box;  // what the picture is framed on, in the world
  Mat3 linear, normalToWorld;
  Vec3 offset;
};
Image renderMesh(const GpuMeshView& mesh, const MeshRenderOptions& options = {});
// Sets view's maps to the world to a volume's index-to-world map (for positions in its voxel index
// coordinates; its direction orthonormal, as every volume read is), and its box to the world box
// round `voxelBox` (the positions' box in voxel index coordinates) so mapped: the mesh's own box
// where the volume's axes are the world's (up to order and sign), a little wider for an oblique one.
void placeInVolume(GpuMeshView& view, const Volume& geometry, const Box& voxelBox);

}  // namespace isoatlas::render
