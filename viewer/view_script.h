// A scripted viewer session (`isoatlas view FILE --script ACTIONS.txt`): one action per line, words
// separated by spaces, `#` to the end of a line a comment, points in world mm (RAS) as X,Y,Z. The
// actions (docs/view-script.md documents them with an example):
//   open FILE                 a volume (segmentation mode), a model (.isoatlas) or a tree (.dvt)
//   mode segment|mesh|tree    which view the window shows
//   tool navigate|probe|seed|unseed|brush   what a click on the slices (or a ctrl-click in 3D) does
//   slice X,Y,Z               the point the three slices pass through
//   probe X,Y,Z[,R]           T and eps from the mean and deviation in a ball (R mm, default 3)
//   seed X,Y,Z,R              a ball added to the segmentation (model on)
//   unseed X,Y,Z,R            a ball carved out (model off)
//   set t|eps|alpha VALUE     a speed parameter
//   topology free|preserve    whether the front keeps the seeds' topology (segment --topology)
//   fill-threads              the threads of background a preserved front leaves to its would-be
//                             cavities filled, as segment does once converged (undoable)
//   run N                     N solver steps (a few per frame; the script waits for them)
//   undo                      back to before the last seed, unseed, brush or stroke (32 deep)
//   redo                      the last undone edit again
//   brush union|subtract SHAPE   a volume-tree edit of the segmentation (SHAPE as `isoatlas edit` takes it)
//   stroke union|subtract R X,Y,Z [X,Y,Z ...]   a sphere brush of R mm dragged through the points (one
//                             stroke: one tree, a write a dab, one undo); in tree mode it paints the
//                             tree on show, a dab a frame
//   paint union|subtract R i|j|k X,Y,Z [X,Y,Z ...]   the same kept to one slice of voxels, normal to
//                             voxel axis i, j or k through the first point (a 2D brush)
//   view3d volume|surface     the 3D view: volume rendering from the pages, or the extracted surface
//   clip +x|-x|+y|-y|+z|-z|off   a clipping plane through the slice point; the side named is cut away
//   build                     extract the surface and build the model (in the background; the script waits)
//   levels CPU GPU            the mesh view's CPU level and GPU halvings
//   wireframe on|off          the mesh view's wireframe
//   stamp X,Y,Z,R,DEPTH WORD  the word pressed DEPTH mm into the model nearest X,Y,Z, in a disc of R mm
//   render raycast|cubes      the tree view's renderer
//   load-mask FILE            the segmentation replaced by a mask volume (> 0 inside; the scan's grid)
//   save-mask FILE            the segmentation as a mask volume
//   save-model FILE           the built model (.isoatlas)
//   save-tree FILE            the tree on show, as painted (.dvt)
//   screenshot FILE.png       the window as it is
//   frames N                  draw N frames
//   quit                      close the window
// readViewScript checks every line before the window opens: a bad one is an Error naming FILE:LINE.
#pragma once
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace isoatlas::viewer {

struct ViewAction {
  std::string verb;             // as written: open, mode, ...
  int line = 0;                 // in the script, for messages
  std::string word;             // open/save/screenshot's file, mode, set's parameter, brush's shape, render's mode, paint's axis
  std::vector<double> numbers;  // a point (and radius), a value, counts, levels; a stroke's radius, then its points
  bool on = true;               // brush union (else subtract), wireframe on
  std::string where() const;    // "FILE:LINE" of the script, for errors met while running
  std::string script;
};

std::vector<ViewAction> readViewScript(const std::string& path);

namespace window {
class Viewer;
}

// Replays a script's actions on the window one per frame, waiting where an action takes time.
class ScriptPlayer {
public:
  explicit ScriptPlayer(std::vector<ViewAction> actions) : actions_(std::move(actions)) {}
  bool finished() const { return next_ >= actions_.size(); }
  // The next action, unless the viewer is still busy with the last; screenshots and quit are left
  // to the end of the frame. Throws Error naming the script's line when an action (or the build it
  // started) fails.
  void step(window::Viewer& viewer, std::string& screenshot, bool& quit);

private:
  void perform(const ViewAction& a, window::Viewer& v, std::string& screenshot, bool& quit);
  std::vector<ViewAction> actions_;
  std::size_t next_ = 0;
  int framesLeft_ = 0;
};

}  // namespace isoatlas::viewer
