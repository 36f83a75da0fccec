// Camera: a perspective view of the scene, as `isoatlas render --camera` gives it (eye, target,
// vertical field of view) on an image of width x height pixels, z up.
//   viewProjection(): the GL matrix (column-major, clip depth -1..1) for the given near and far
//   pixelsPerUnit(): how many pixels one world unit (mm) at `point` covers on the image
//   turned(): the camera rotated about the vertical axis through its target (turntables)
//   framing(): the camera that shows a box whole, seen along a direction
#pragma once
#include <array>

#include "core/mesh.h"

namespace isoatlas::render {

struct Camera {
  Vec3 eye{0, -1, 0}, target{0, 0, 0}, up{0, 0, 1};
  double fovDegrees = 30;
  int width = 800, height = 600;

  // Throws Error(BadInput) when the eye sits on the target, looks along `up`, or the field of view
  // or image size are out of range.
  void check() const;
  std::array<float, 16> viewProjection(double near, double far) const;
  double pixelsPerUnit(const Vec3& point) const;  // at the point's depth; huge behind the eye
  Camera turned(double radians) const;
  // The unit direction from the eye through picture position (x, y) (pixels, top-left origin; a
  // pixel's centre at +0.5): for picking with the mouse.
  Vec3 rayThrough(double x, double y) const;
  static Camera framing(const Box& box, int width, int height, Vec3 viewDirection = {0, 1, 0});
};

// Near and far planes that hold `box` (a sphere around it) in front of the camera.
std::array<double, 2> depthRange(const Camera& camera, const Box& box);

// Transforms as the shaders take them: 4x4, column-major.
using Mat4 = std::array<float, 16>;
Mat4 inverse(const Mat4& m);
std::array<float, 9> normalMatrix(const Mat4& m);  // the inverse transpose of the upper 3x3, column-major
// A voxel grid's index-to-world transform: world = origin + direction * (spacing .* index).
Mat4 gridToWorld(const Mat3& direction, const Vec3& spacing, const Vec3& origin);

}  // namespace isoatlas::render
