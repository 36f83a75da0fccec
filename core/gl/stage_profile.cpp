#include "core/gl/stage_profile.h"

#include <epoxy/gl.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/gl/context.h"

namespace isoatlas::gl {
namespace {

std::atomic<bool> g_driverNotes{false};
std::atomic<int> g_driverNotesPrinted{0};
constexpr int kDriverNotes = 100;

void GLAPIENTRY onDriverMessage(GLenum, GLenum type, GLuint, GLenum, GLsizei, const GLchar* message, const void*) {
  noteDriverMessage(type, message);
}

}  // namespace

bool stageProfileRequested() {
  const char* v = std::getenv("ISOATLAS_GL_PROFILE");
  return v && std::strcmp(v, "1") == 0;
}

StageProfile::StageProfile(const char* what, int reportEvery) : what_(what), on_(stageProfileRequested()) {
  if (!on_) return;
  reportEvery_ = reportEvery > 0 ? reportEvery : 1;
  stages_.reserve(16);
}

StageProfile::~StageProfile() {
  if (!on_) return;
  // The last stage ends with a glFinish only while a context of ours is current (an object destroyed
  // after its context still prints what it has). The callers' time after the last stage is not counted.
  if (running_) {
    try {
      Context::current();
      switchTo(nullptr);
    } catch (...) {
      running_ = nullptr;
    }
  }
  if (inCall_) ++calls_;
  if (calls_ > 0) print();
}

void StageProfile::add(const char* name, double ms) {
  Stage* s = nullptr;
  for (Stage& t : stages_)
    if (t.name == name || std::strcmp(t.name, name) == 0) s = &t;
  if (!s) s = &stages_.emplace_back(Stage{name});
  s->ms += ms;
  ++s->count;
}

void StageProfile::switchTo(const char* name) {
  if (!running_ && !name && !inCall_) return;
  glFinish();
  const auto now = std::chrono::steady_clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - started_).count();
  if (running_) add(running_, ms);
  else if (inCall_) add("outside these stages", ms);
  running_ = name;
  started_ = now;
  if (name) inCall_ = true;
}

void StageProfile::finishCall() {
  if (!inCall_) return;
  switchTo(nullptr);
  inCall_ = false;
  if (++calls_ >= reportEvery_) print();
}

void StageProfile::print() {
  const int calls = calls_ > 0 ? calls_ : 1;
  double sum = 0;
  for (const Stage& s : stages_) {
    const double ms = s.ms / calls;
    sum += ms;
    if (calls == 1) {
      if (s.count > 1) std::fprintf(stderr, "isoatlas gl profile: %s: %s: %.3f ms (x%ld)\n", what_, s.name, ms, s.count);
      else std::fprintf(stderr, "isoatlas gl profile: %s: %s: %.3f ms\n", what_, s.name, ms);
    } else {
      std::fprintf(stderr, "isoatlas gl profile: %s (mean of %d calls): %s: %.3f ms (x%.2f a call)\n", what_, calls,
                   s.name, ms, double(s.count) / calls);
    }
  }
  if (calls == 1) std::fprintf(stderr, "isoatlas gl profile: %s: total: %.3f ms\n", what_, sum);
  else std::fprintf(stderr, "isoatlas gl profile: %s (mean of %d calls): total: %.3f ms\n", what_, calls, sum);
  stages_.clear();
  calls_ = 0;
}

void noteDriverMessage(unsigned type, const char* message) {
  if (!g_driverNotes.load(std::memory_order_relaxed)) return;
  if (type != GL_DEBUG_TYPE_PERFORMANCE && type != GL_DEBUG_TYPE_OTHER) return;
  if (g_driverNotesPrinted.fetch_add(1) >= kDriverNotes) return;
  std::fprintf(stderr, "isoatlas gl driver: %s\n", message);
}

void enableDriverNotes(bool debugCallbackInstalled) {
  if (!stageProfileRequested()) return;
  g_driverNotes = true;
  glEnable(GL_DEBUG_OUTPUT);
  glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
  if (!debugCallbackInstalled) glDebugMessageCallback(onDriverMessage, nullptr);
}

}  // namespace isoatlas::gl
