// run's engraving of the demo: a word stamped on the model's surface beside the render.
#pragma once
#include <nlohmann/json.hpp>

#include <filesystem>
#include <future>
#include <optional>
#include <string>

#include "app/run_stages.h"
#include "atlas/stamp_detail.h"

namespace isoatlas::app {

// The demo engraves a word on the left hemisphere's lateral surface (fine detail, the paper's Fig. 10).
// The model stands without it: a failure is a skipped stage. The stamp and the engraved model's file
// are made on a thread of their own while this one renders the model (llvmpipe draws its geometry on
// one core); the close-up, which needs the GL context, is drawn here afterwards.
struct Engraving {
  std::optional<atlas::Model> model;
  atlas::StampStats stamped;
  double radius = 0, seconds = 0;
  nlohmann::json figures;
  std::string skipped;  // why not, when it was not made
  bool failed = false;  // the stamp or the file failed (said on stderr), rather than not wanted
};

// Starts the stamp and the engraved model's file on a thread of their own.
std::future<Engraving> startEngraving(const atlas::Model& model, const Mesh& surface, const std::filesystem::path& dir);
// Waits for them, draws the close-up and records the stage (done or skipped).
void finishEngraving(RunJob& job, std::future<Engraving>& engraving);

}  // namespace isoatlas::app
