// Orbit: the window's camera, circling a box: angles about its centre (z up), distance in the box's
// diagonals, the centre moved by panning. Left-drag turns it, right-drag pans, the wheel zooms.
#pragma once
#include <algorithm>
#include <cmath>

#include "render/camera.h"

namespace isoatlas::render {

struct Orbit {
  double yaw = 1.5708, pitch = 0.25, distance = 1.6;  // from the front (anterior, +y), a little above
  Vec3 offset{0, 0, 0};  // of the point it circles from the box's centre, in diagonals
  // From the box's centre towards the eye.
  Vec3 direction() const { return {std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch)}; }
  Camera camera(const Box& box, int width, int height) const {
    const Vec3 centre = (box.min + box.max) * 0.5 + offset * std::max(box.diagonal(), 1e-6);
    Camera c;
    c.target = centre;
    c.eye = centre + direction() * (distance * std::max(box.diagonal(), 1e-6));
    c.width = width, c.height = height;
    return c;
  }
  void drag(double dx, double dy) {
    yaw -= dx * 0.01;
    pitch = std::clamp(pitch + dy * 0.01, -1.5, 1.5);
  }
  // Moves what it circles with the mouse: dx, dy pixels across and down a picture `height` high.
  void pan(double dx, double dy, int height) {
    const Vec3 forward = direction() * -1.0;
    const Vec3 right = unit(cross(forward, Vec3{0, 0, 1})), up = cross(right, forward);
    const double perPixel = 2 * distance * std::tan(Camera{}.fovDegrees * 3.14159265358979 / 360) / std::max(height, 1);
    offset = offset - right * (dx * perPixel) + up * (dy * perPixel);
  }
  void zoom(double wheel) { distance = std::clamp(distance * std::pow(0.9, wheel), 0.05, 20.0); }
};

}  // namespace isoatlas::render
