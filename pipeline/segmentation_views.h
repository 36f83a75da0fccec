// The window's segmentation views made headless (`isoatlas render VOLUME --segmentation S`): the three
// slices with the segmentation's contour and a crosshair, or the volume rendering of the scan and the
// segmentation read from a level set's pages (a clipping plane through the slice point, the scan
// only inside), with the window's default camera.
#pragma once
#include <nlohmann/json.hpp>

#include <optional>
#include <string>

#include "core/image.h"
#include "render/camera.h"

namespace isoatlas::pipeline {

struct SegmentationViewRequest {
  std::string volume, segmentation;  // the scan; a mask or phi volume in its grid (may be empty)
  std::string view;                  // slices (default) or volume
  std::optional<Vec3> at;            // the slice point (world mm); default the volume's centre
  std::string clip = "off";          // +x, -x, +y, -y, +z, -z (the side cut away) or off
  bool insideOnly = false;
  double opacity = 0.08;
  int width = 800, height = 600;
  std::optional<render::Camera> camera;
};

// Reads and checks everything before any GL work; adds view, inside_voxels and size to `figures`.
Image renderSegmentationView(const SegmentationViewRequest& request, nlohmann::json& figures);

}  // namespace isoatlas::pipeline
