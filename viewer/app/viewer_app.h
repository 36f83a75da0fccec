// runViewer: `isoatlas view`, a GLFW window with Dear ImGui panels that shows a file with the same
// renderers the headless commands use, in the window's one GL context:
//   a model (.isoatlas): the tessellated atlas through the cascade (CPU level, GPU level, wireframe),
//     orbit with the left mouse button, zoom with the wheel;
//   a volume tree (.dvt): ray cast or cubes;
//   a volume: axial, coronal and sagittal slices, the slice point moved by sliders.
// `frames` > 0 draws that many frames and returns (with `screenshot`, the last one saved as PNG);
// P saves a screenshot too (isoatlas_view_NNN.png in the working folder).
// Not yet: steering the segmentation, brushes, scripted actions (the viewer issue's note lists them).
#pragma once
#include <string>
#include <vector>

namespace isoatlas::viewer {

struct ViewerOptions {
  std::vector<std::string> files;
  int frames = 0;          // 0: until the window is closed
  std::string screenshot;  // with frames: the last frame as PNG
  int width = 1280, height = 800;
};

// Throws Error (BadInput) when there is no display or a file cannot be read.
void runViewer(const ViewerOptions& options);

}  // namespace isoatlas::viewer
