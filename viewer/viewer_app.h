// runViewer: `isoatlas view`, a GLFW window with Dear ImGui panels, every GPU stage in its one context:
//   segment: axial, coronal and sagittal slices of a volume with the level set's contour and the speed
//     as overlays (scroll with the wheel), steered live as in ITK-SNAP's snake mode: probe T and eps,
//     seed in and out, run / pause / step, T, eps and alpha while it runs, undo, save the mask; beside
//     them the level set's surface extracted from its pages; volume-tree brushes on the slices; the
//     model extracted and built from the segmentation in the background (a progress bar);
//   mesh: a model (.isoatlas) through the cascade: CPU level or view-dependent refinement, GPU level,
//     wireframe (tile sides and interior edges), chart colours, the atlas in a side panel, the grid;
//   tree: a volume tree (.dvt, or the last brush's) ray cast or as cubes, painted with a sphere brush
//     (ctrl-drag; each dab drawn in the frame after it, from the tree passes' own buffers on the GPU).
// Orbit with the left mouse button, zoom with the wheel; P or the menu saves the window as PNG.
// A script (view_script.h) replays actions; `frames` > 0 draws that many frames and returns.
#pragma once
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/vec.h"
#include "core/volume_io.h"
#include "viewer/model_job.h"

namespace isoatlas::viewer {

// The window's layout: the controls on the right, kControlsWidth pixels wide; the views fill the rest.
// In segment mode the three slices run across the top, each slicePanelSize pixels square
// (renderSlices's picture, pixel for pixel), and the level set's surface fills the space below.
inline constexpr int kControlsWidth = 340;
int slicePanelSize(int width, int height);

struct ViewerOptions {
  std::vector<std::string> files;  // opened in turn: volumes, models, trees
  std::string script;              // actions to replay (view_script.h)
  int frames = 0;                  // 0: until the window is closed (or the script quits)
  std::string screenshot;          // with frames: the last frame as PNG
  int width = 1280, height = 800;
  std::string backend = "auto";    // the segmentation's solver: gpu, cpu, auto (the CPU when the window's GL is software)
  ModelBuilder buildModel;         // the `build` stage (the CLI passes its own); none: building is off
  // Called at the start of each frame (0, 1, ...), before the window's events are polled: input
  // injected into the display here (tests use XTest) reaches the handlers as a user's does.
  std::function<void(int frame)> beforeFrame;
  // --volume, --series: the volumes among `files` (last: GCC 12 warns of a designated initialiser
  // that skips an aggregate of strings before the members it names).
  VolumeReadOptions read;
};

struct ModeFrames {
  int frames = 0;
  double meanMs = 0, maxMs = 0;
};
struct ViewerReport {
  std::map<std::string, ModeFrames> modes;  // per view: segment, mesh, tree
  int iterations = 0;                       // solver steps taken
  std::string backend;                      // the segmentation's solver
  std::string status;                       // the status line as the window closed
  Vec3 slicePoint{0, 0, 0};                 // where the slices crossed as it closed (with a volume open)
  std::vector<double> treeDabMs;            // each tree dab's latency: its write to its picture drawn
};

// Throws Error (BadInput) when there is no display, a file cannot be read or a script action fails
// (naming the script's line).
ViewerReport runViewer(const ViewerOptions& options);

}  // namespace isoatlas::viewer
