#include "core/progress.h"

#include <unistd.h>

#include <cstdio>

namespace isoatlas {
namespace {
bool g_quiet = false;
thread_local std::shared_ptr<const Progress::Observer> t_observer;  // ProgressObserver's, innermost
}  // namespace

ProgressObserver::ProgressObserver(Progress::Observer observer) : previous_(std::move(t_observer)) {
  t_observer = std::make_shared<const Progress::Observer>(std::move(observer));
}

ProgressObserver::~ProgressObserver() { t_observer = std::move(previous_); }

void Progress::notify(bool final) {
  if (!observer_) return;
  const auto now = std::chrono::steady_clock::now();
  if (!final && now - lastNotify_ < std::chrono::milliseconds(50)) return;
  lastNotify_ = now;
  (*observer_)(task_, final || !total_ ? 1.0 : double(done_) / double(total_));
}

void Progress::setQuiet(bool quiet) { g_quiet = quiet; }
bool Progress::quiet() { return g_quiet; }

void logInfo(const std::string& line) {
  if (!g_quiet) std::fprintf(stderr, "%s\n", line.c_str());
}

Progress::Progress(std::string task, std::uint64_t total, std::string unit)
    : observer_(t_observer), task_(std::move(task)), unit_(std::move(unit)), total_(total), start_(std::chrono::steady_clock::now()),
      lastPrint_(start_), lastNotify_(start_), tty_(isatty(STDERR_FILENO) == 1) {}

Progress::~Progress() {
  try {
    finish();
  } catch (...) {  // the observer stopping work that is ending anyway (a destructor must not throw)
  }
}

void Progress::update(std::uint64_t done) {
  done_ = done;
  if (finished_) return;
  notify(false);
  if (g_quiet) return;
  const auto now = std::chrono::steady_clock::now();
  const auto interval = tty_ ? std::chrono::milliseconds(100) : std::chrono::milliseconds(5000);
  if (now - lastPrint_ < interval) return;
  lastPrint_ = now;
  print(false);
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  notify(true);
  if (!g_quiet) print(true);
}

void Progress::print(bool final) {
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = seconds > 0 ? double(done_) / seconds : 0;
  const double fraction = total_ ? double(done_) / double(total_) : 1.0;
  const double eta = rate > 0 && total_ > done_ ? double(total_ - done_) / rate : 0;
  if (tty_) {
    constexpr int kWidth = 30;
    const int filled = int(fraction * kWidth + 0.5);
    std::fprintf(stderr, "\r%s [%-*s] %3.0f%% %.1f %s/s ETA %.0fs \033[K%s", task_.c_str(), kWidth,
                 std::string(std::size_t(filled > kWidth ? kWidth : filled), '#').c_str(), fraction * 100, rate,
                 unit_.empty() ? "it" : unit_.c_str(), eta, final ? "\n" : "");
  } else if (final) {
    std::fprintf(stderr, "%s: done, %llu %s in %.2f s\n", task_.c_str(), (unsigned long long)done_,
                 unit_.c_str(), seconds);
  } else {
    std::fprintf(stderr, "%s: %.0f%% (%llu/%llu %s, %.1f/s, ETA %.0f s)\n", task_.c_str(), fraction * 100,
                 (unsigned long long)done_, (unsigned long long)total_, unit_.c_str(), rate, eta);
  }
  std::fflush(stderr);
}

}  // namespace isoatlas
