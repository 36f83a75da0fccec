// renderMesh: a picture of a triangle mesh, lit, framed on its bounding box, seen from a direction,
// drawn offscreen in the current GL context (gl::Context::current(), checked: headless EGL on a GPU or
// Mesa's llvmpipe, or a window's).
//   mesh:      triangles in world coordinates (normals are computed from the faces)
//   options:   image size, view direction (from the camera into the scene), up vector, colours
// Returns an RGB image, rows top to bottom.
#pragma once
#include "core/image.h"
#include "core/mesh.h"

namespace isoatlas::render {

struct MeshRenderOptions {
  int width = 800, height = 600;
  Vec3 viewDirection{0, 1, 0};  // from the camera into the scene (default: from the front, RAS +y)
  Vec3 up{0, 0, 1};
  Vec3 colour{0.93, 0.78, 0.62};
  Vec3 background{1, 1, 1};
};

Image renderMesh(const Mesh& mesh, const MeshRenderOptions& options = {});

}  // namespace isoatlas::render
