// StageProfile: wall time per named stage of a GPU path, for finding where the time goes on a real GPU.
// Off unless the environment has ISOATLAS_GL_PROFILE=1 (read when the object is made): then each stage
// ends with glFinish, so a stage's time is its own GPU work and CPU work (and none of it is left queued
// for the next), and the times go to stderr as lines
//   isoatlas gl profile: extract gpu: classify cells: 1.234 ms
// When off, every member is one test of a bool: no glFinish, no clock, nothing printed, nothing else
// changes. glFinish needs the current GL context: profile only code that runs in one.
//   One object per call (extraction): stage("a"), stage("b") ... ; the destructor ends the last stage
//   and prints the call's stages (a stage named twice in a call adds up, "(x2)") and their sum.
//   A long-lived one (a solver's iterations): end() closes a stage where work of its callers follows,
//   endCall() closes a call; every `reportEvery` calls, and what is left when it is destroyed, it
//   prints each stage's mean per call over those calls. Time inside a call but outside its stages (the
//   callers' work between two of them, up to endCall) is the stage "outside these stages".
// With the variable set, the context also prints the driver's performance and memory-placement notes
// (GL debug output, types performance and other; the first 100) as "isoatlas gl driver: ..." lines.
#pragma once
#include <chrono>
#include <vector>

namespace isoatlas::gl {

// Whether ISOATLAS_GL_PROFILE=1 is set now.
bool stageProfileRequested();

class StageProfile {
public:
  explicit StageProfile(const char* what, int reportEvery = 1);
  ~StageProfile();
  StageProfile(const StageProfile&) = delete;
  StageProfile& operator=(const StageProfile&) = delete;

  bool on() const { return on_; }
  // Ends the stage running (if any) and starts `name` (a string that outlives this object).
  void stage(const char* name) {
    if (on_) switchTo(name);
  }
  // Ends the stage running, starting none.
  void end() {
    if (on_) switchTo(nullptr);
  }
  // Ends the stage running and the call (if a stage ran in it); prints when `reportEvery` calls have
  // ended since the last print.
  void endCall() {
    if (on_) finishCall();
  }

private:
  struct Stage {
    const char* name;
    double ms = 0;
    long count = 0;
  };
  void switchTo(const char* name);
  void finishCall();
  void add(const char* name, double ms);
  void print();

  const char* what_;
  bool on_;
  int reportEvery_ = 1, calls_ = 0;
  const char* running_ = nullptr;
  bool inCall_ = false;  // a stage has started since the last endCall
  std::chrono::steady_clock::time_point started_;
  std::vector<Stage> stages_;  // in the order first run
};

// For Context: prints a GL debug message of type performance or other when profiling was asked for
// (the first 100), e.g. NVIDIA's "Buffer detailed info: ... will use VIDEO memory ...".
void noteDriverMessage(unsigned type, const char* message);
// Turns GL debug output on in the current context and sends its messages to noteDriverMessage, when
// profiling is asked for and no other debug callback is installed (release builds); else nothing.
void enableDriverNotes(bool debugCallbackInstalled);

}  // namespace isoatlas::gl
