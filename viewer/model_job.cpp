#include "viewer/model_job.h"

#include "core/error.h"
#include "core/progress.h"

namespace isoatlas::viewer {

ModelJob::ModelJob(Mesh surface, const ModelBuilder& build) : start_(std::chrono::steady_clock::now()) {
  result_ = std::async(std::launch::async, [this, surface = std::move(surface), build] {
    // The worker's own observer: the build's Progress is made on this thread.
    const ProgressObserver watch([this](const std::string& task, double fraction) {
      if (cancelled_) throw Error("the model's build was stopped", ErrorKind::Failure);
      const std::lock_guard lock(mutex_);
      task_ = task, fraction_ = fraction;
    });
    return build(surface);
  });
}

ModelJob::~ModelJob() {
  cancelled_ = true;
  if (result_.valid()) result_.wait();
}

bool ModelJob::done() const { return result_.valid() && result_.wait_for(std::chrono::seconds(0)) == std::future_status::ready; }

atlas::Model ModelJob::take() { return result_.get(); }

std::pair<std::string, double> ModelJob::progress() const {
  const std::lock_guard lock(mutex_);
  return {task_, fraction_};
}

double ModelJob::seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

}  // namespace isoatlas::viewer
