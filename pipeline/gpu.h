// Gpu: the backend a stage runs on and the process's one GL context, which the caller (a command, the
// Python module) owns; chooseBackend makes it from "gpu", "cpu" or "auto".
#pragma once
#include <memory>
#include <string>

#include "core/gl/context.h"
#include "levelset/level_set.h"

namespace isoatlas::pipeline {

// The backend a command runs on, and the one GL context of its process. The caller owns it: made
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

}  // namespace isoatlas::pipeline
