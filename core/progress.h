// Progress on long work, on stderr: a bar with rate and ETA when stderr is a terminal, a plain line
// every few seconds otherwise (logs, CI), nothing when quiet. Cheap to call in a loop.
#pragma once
#include <chrono>
#include <cstdint>
#include <functional>
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
  // Also tells `observer` (task, fraction done) at most every 50 ms and when finished, from whichever
  // thread updates: a window's progress bar for work it runs in the background. Empty: none. The
  // observer may throw to stop the work (a build the window no longer wants, Ctrl-C in Python): the
  // exception leaves update() or finish(); the destructor swallows it.
  using Observer = std::function<void(const std::string& task, double fraction)>;
  static void setObserver(Observer observer);

private:
  void print(bool final);
  std::string task_, unit_;
  std::uint64_t total_, done_ = 0;
  void notify(bool final);
  std::chrono::steady_clock::time_point start_, lastPrint_, lastNotify_;
  bool tty_, finished_ = false;
};

// One informational line on stderr, unless quiet.
void logInfo(const std::string& line);

}  // namespace isoatlas
