// run's view-window script (docs/view-script.md): run's segmentation and edits replayed in the window.
#pragma once
#include <string>
#include <vector>

#include "core/volume.h"
#include "levelset/solver_backend.h"
#include "levelset/speed.h"
#include "pipeline/seed_ball.h"
#include "pipeline/volume_editing.h"

namespace isoatlas::app {

// A view-window script (docs/view-script.md) doing what run did, seen in the window: the same
// parameters and segmentation, the same edits as brushes, then the model built. The segmentation is
// the seeds and steps (the same solver: the same segmentation), or, where it started at half
// resolution (startedFrom: its mask's file), that mask. With the topology preserved: the steps up to
// the threads' filling, the filling, and the iterationsAfterFill after it.
void writeViewSession(const std::string& path, const std::string& input, const Volume& volume, const levelset::SpeedParams& params,
                      const std::vector<pipeline::Ball>& seeds, int iterations, const std::string& startedFrom,
                      const std::vector<pipeline::EditStep>& edits, levelset::Topology topology = levelset::Topology::Free,
                      int iterationsAfterFill = 0);

}  // namespace isoatlas::app
