#include "render/camera.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace isoatlas::render {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Frame {
  Vec3 right, up, forward;
};
Frame frameOf(const Camera& c) {
  const Vec3 forward = unit(c.target - c.eye);
  const Vec3 right = unit(cross(forward, c.up));
  return {right, cross(right, forward), forward};
}

}  // namespace

void Camera::check() const {
  require(norm(target - eye) > 0, "--camera: the eye and the target are the same point");
  require(norm(cross(target - eye, up)) > 1e-9 * norm(target - eye), "--camera: the camera looks straight up or down");
  require(fovDegrees > 0.1 && fovDegrees < 170, "--camera: the field of view must lie between 0.1 and 170 degrees");
  require(width > 0 && height > 0 && width <= 8192 && height <= 8192, "--size: width and height must be 1 to 8192 pixels");
}

std::array<float, 16> Camera::viewProjection(double near, double far) const {
  const Frame f = frameOf(*this);
  const double focal = 1 / std::tan(fovDegrees * kPi / 360), aspect = double(width) / height;
  // Rows of the projection times the view, written column-major for GL.
  const double a = -(far + near) / (far - near), b = -2 * far * near / (far - near);
  const Vec3 rows[3] = {f.right * (focal / aspect), f.up * focal, f.forward};
  std::array<float, 16> m{};
  for (int c = 0; c < 3; ++c) {
    m[c * 4 + 0] = float(rows[0][c]);
    m[c * 4 + 1] = float(rows[1][c]);
    m[c * 4 + 2] = float(-a * rows[2][c]);  // depth grows along forward
    m[c * 4 + 3] = float(rows[2][c]);
  }
  m[12] = float(-dot(rows[0], eye));
  m[13] = float(-dot(rows[1], eye));
  m[14] = float(a * dot(rows[2], eye) + b);
  m[15] = float(-dot(rows[2], eye));
  return m;
}

Vec3 Camera::rayThrough(double x, double y) const {
  const Frame f = frameOf(*this);
  const double t = std::tan(fovDegrees * kPi / 360), aspect = double(width) / height;
  return unit(f.forward + f.right * ((2 * x / width - 1) * t * aspect) + f.up * ((1 - 2 * y / height) * t));
}

double Camera::pixelsPerUnit(const Vec3& point) const {
  const double depth = dot(point - eye, frameOf(*this).forward);
  const double focalPixels = height / 2.0 / std::tan(fovDegrees * kPi / 360);
  return focalPixels / std::max(depth, 1e-6 * norm(target - eye));
}

Camera Camera::turned(double radians) const {
  const Vec3 axis = unit(up), d = eye - target;
  const Vec3 along = axis * dot(d, axis), across = d - along, side = cross(axis, across);
  Camera c = *this;
  c.eye = target + along + across * std::cos(radians) + side * std::sin(radians);
  return c;
}

Camera Camera::framing(const Box& box, int width, int height, Vec3 viewDirection) {
  Camera c;
  c.width = width, c.height = height;
  c.target = (box.min + box.max) * 0.5;
  c.eye = c.target - unit(viewDirection);
  const Frame f = frameOf(c);
  // Back far enough that every corner of the box lies inside the view, with a 5 % margin.
  const double tanV = std::tan(c.fovDegrees * kPi / 360), tanH = tanV * width / height;
  double distance = 1e-6;
  for (int k = 0; k < 8; ++k) {
    const Vec3 corner{(k & 1) ? box.max.x : box.min.x, (k & 2) ? box.max.y : box.min.y, (k & 4) ? box.max.z : box.min.z};
    const Vec3 d = corner - c.target;
    const double depth = dot(d, f.forward);
    distance = std::max({distance, std::fabs(dot(d, f.right)) * 1.05 / tanH - depth, std::fabs(dot(d, f.up)) * 1.05 / tanV - depth});
  }
  c.eye = c.target - f.forward * distance;
  return c;
}

std::array<double, 2> depthRange(const Camera& camera, const Box& box) {
  const Vec3 centre = (box.min + box.max) * 0.5;
  const double radius = std::max(box.diagonal() / 2, 1e-6);
  const double depth = dot(centre - camera.eye, unit(camera.target - camera.eye));
  const double far = std::max(depth + radius, radius * 1e-3) * 1.01;
  return {std::max(depth - radius, far * 1e-4), far};
}

Mat4 gridToWorld(const Mat3& direction, const Vec3& spacing, const Vec3& origin) {
  Mat4 m{};
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) m[std::size_t(4 * c + r)] = float(direction.m[r][c] * spacing[c]);
  for (int r = 0; r < 3; ++r) m[std::size_t(12 + r)] = float(origin[r]);
  m[15] = 1;
  return m;
}

// Gauss-Jordan in double.
Mat4 inverse(const Mat4& m) {
  double a[4][8];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 8; ++c) a[r][c] = c < 4 ? m[std::size_t(4 * c + r)] : (c - 4 == r ? 1 : 0);
  for (int c = 0; c < 4; ++c) {
    int pivot = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::abs(a[r][c]) > std::abs(a[pivot][c])) pivot = r;
    std::swap(a[c], a[pivot]);
    const double p = a[c][c];
    for (double& x : a[c]) x /= p;
    for (int r = 0; r < 4; ++r)
      if (r != c) {
        const double k = a[r][c];
        for (int j = 0; j < 8; ++j) a[r][j] -= k * a[c][j];
      }
  }
  Mat4 out{};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out[std::size_t(4 * c + r)] = float(a[r][c + 4]);
  return out;
}

std::array<float, 9> normalMatrix(const Mat4& m) {
  const Mat4 inv = inverse(m);
  std::array<float, 9> n{};
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) n[std::size_t(3 * c + r)] = inv[std::size_t(4 * r + c)];
  return n;
}

}  // namespace isoatlas::render
