// Orbit: the window's camera, circling a box: angles about its centre (z up), distance in the box's
// diagonals. Left-drag turns it, the wheel zooms.
#pragma once
#include <algorithm>
#include <cmath>

#include "viewer/camera.h"

namespace isoatlas::viewer {

struct Orbit {
  double yaw = 1.5708, pitch = 0.25, distance = 1.6;  // from the front (anterior, +y), a little above
  // From the box's centre towards the eye.
  Vec3 direction() const { return {std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch)}; }
  Camera camera(const Box& box, int width, int height) const {
    const Vec3 centre = (box.min + box.max) * 0.5;
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
  void zoom(double wheel) { distance = std::clamp(distance * std::pow(0.9, wheel), 0.05, 20.0); }
};

}  // namespace isoatlas::viewer
