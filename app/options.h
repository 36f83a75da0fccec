// Parsing helpers shared by subcommands: points "X,Y,Z[,R]" and the --backend choice.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/gl/context.h"

#include "core/numbers.h"
#include "core/vec.h"
#include "core/volume.h"
#include "levelset/level_set.h"

namespace isoatlas::app {

struct Ball {
  Vec3 centre;
  double radius;
};
// "X,Y,Z" or "X,Y,Z,R" (R defaults to defaultRadius); throws Error naming `option` on bad text.
Ball parseBall(const std::string& text, const std::string& option, double defaultRadius);
// "W,H": whole pixels from 1 to 8192; throws Error naming --size otherwise.
std::array<int, 2> parseSize(const std::string& text);
// Throws Error unless the voxel index lies inside the volume.
void requireInside(const Volume& v, const Vec3& index, const std::string& what);

// The backend a command runs on, and the one GL context of its process. The command owns it: made
// here or by needGl(), current until the command ends, and destroyed after every GL object made in
// it (declare it before them). GPU stages use it, never one of their own.
struct Gpu {
  levelset::Backend backend = levelset::Backend::Cpu;
  std::string renderer = "cpu";          // the GL renderer the GPU backend runs on, or "cpu"
  std::unique_ptr<gl::Context> context;  // null until a choice or a render needs one

  // The context, made (headless) on the first call; for work that needs GL on any backend (renders).
  gl::Context& needGl();
};

// "gpu", "cpu" or "auto": auto takes the GPU when one is there, and the CPU backend (with a line
// saying so) when the only GL is a software rasteriser. gpu and auto make the process's context (auto
// keeps it even when it chooses the CPU, so later renders make no second one).
Gpu chooseBackend(const std::string& choice);


}  // namespace isoatlas::app
