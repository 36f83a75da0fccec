// ModelJob: a model built from a surface in the background, so the window keeps drawing: a worker
// thread runs the build (CPU only, no GL) and reports progress through core/progress's observer; the
// window polls it each frame and takes the model when it is done. A job destroyed before it is done
// (the window closed mid-build) stops the build at its next progress update.
#pragma once
#include <atomic>
#include <functional>
#include <future>
#include <mutex>
#include <optional>
#include <string>

#include "atlas/model_file.h"
#include "core/mesh.h"

namespace isoatlas::viewer {

using ModelBuilder = std::function<atlas::Model(const Mesh& surface)>;

class ModelJob {
public:
  ModelJob(Mesh surface, const ModelBuilder& build);
  ~ModelJob();  // stops the build at its next progress update, and waits for the worker
  bool done() const;
  // The model once done (rethrows the build's error); call once.
  atlas::Model take();
  // What the build is doing now, and how far that stage is (0..1).
  std::pair<std::string, double> progress() const;
  double seconds() const;

private:
  mutable std::mutex mutex_;
  std::atomic<bool> cancelled_{false};
  std::string task_ = "starting";
  double fraction_ = 0;
  std::chrono::steady_clock::time_point start_;
  std::future<atlas::Model> result_;
};

}  // namespace isoatlas::viewer
