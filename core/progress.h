// Progress on long work, on stderr: a bar with rate and ETA when stderr is a terminal, a plain line
// every few seconds otherwise (logs, CI), nothing when quiet. Cheap to call in a loop.
#pragma once
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace isoatlas {

class Progress {
public:
  Progress(std::string task, std::uint64_t total, std::string unit = "");
  ~Progress();
  void update(std::uint64_t done);  // done out of total
  void finish();                    // prints the closing line once

  static void setQuiet(bool quiet);
  static bool quiet();
  // A Progress also tells the observer of the thread that made it (ProgressObserver below), if any,
  // (task, fraction done) at most every 50 ms and when finished, from whichever thread updates. The
  // observer may throw to stop the work (a build the window no longer wants, Ctrl-C in Python): the
  // exception leaves update() or finish(); the destructor swallows it.
  using Observer = std::function<void(const std::string& task, double fraction)>;

private:
  std::shared_ptr<const Observer> observer_;  // the making thread's, kept while this lives
  void print(bool final);
  std::string task_, unit_;
  std::uint64_t total_, done_ = 0;
  void notify(bool final);
  std::chrono::steady_clock::time_point start_, lastPrint_, lastNotify_;
  bool tty_, finished_ = false;
};

// The observer of the Progress made on this thread while it lives: a window's progress bar for the
// build its worker thread runs, a Python call's callback. Each thread has its own, so two calls on two
// threads see their own progress only, and nothing is locked to hand progress over (a global observer
// took a lock, then the GIL, while Python's side held the GIL and wanted the lock). Nested ones stack:
// the innermost is current until it ends. Make and end it on the same thread.
class ProgressObserver {
public:
  explicit ProgressObserver(Progress::Observer observer);
  ~ProgressObserver();
  ProgressObserver(const ProgressObserver&) = delete;
  ProgressObserver& operator=(const ProgressObserver&) = delete;

private:
  std::shared_ptr<const Progress::Observer> previous_;
};

// One informational line on stderr, unless quiet.
void logInfo(const std::string& line);

}  // namespace isoatlas
