// Shared by the benchmarks: timing, peak memory, the machine's name, and the JSON line each
// measurement prints (scripts/run-bench collects them into bench/RESULTS.md).
#pragma once
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

namespace isoatlas::bench {

inline std::string machineName() {
  std::ifstream cpu("/proc/cpuinfo");
  std::string line, model = "unknown CPU";
  while (std::getline(cpu, line))
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  return model + ", " + std::to_string(sysconf(_SC_NPROCESSORS_ONLN)) + " cores";
}

// Median wall time of `runs` calls, in seconds.
inline double medianSeconds(int runs, const std::function<void()>& work) {
  std::vector<double> t;
  for (int i = 0; i < runs; ++i) {
    const auto start = std::chrono::steady_clock::now();
    work();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

inline double peakRssMiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;
}

// One measurement: ours beside the peer's, from the same run. lowerIsBetter decides the ratio's sense:
// ratio > 1 always means isoatlas is ahead.
// The machine's memory bandwidth in bytes a second, as STREAM's triad measures it: a[i] = b[i] + s c[i]
// over arrays far larger than the caches, split over every core, 24 bytes an element; the best of
// five.
inline double memoryBandwidth() {
  const std::size_t n = std::size_t(1) << 25;  // 32 M doubles, 256 MiB an array
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  double best = 0;
  for (int run = 0; run < 5; ++run) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::thread> workers;
    for (unsigned t = 0; t < threads; ++t)
      workers.emplace_back([&, t] {
        for (std::size_t i = n * t / threads, end = n * (t + 1) / threads; i < end; ++i) a[i] = b[i] + 3.0 * c[i];
      });
    for (std::thread& w : workers) w.join();
    best = std::max(best, 24.0 * double(n) / std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  if (a[n / 2] != 7.0) std::abort();  // the stores were made
  return best;
}

inline void report(const std::string& bench, const std::string& caseName, const std::string& metric, double ours,
                   const std::string& peer, double theirs, bool lowerIsBetter = true, const std::string& device = "") {
  nlohmann::json j{{"bench", bench},  {"case", caseName}, {"metric", metric},
                   {"isoatlas", ours}, {"peer", peer},    {"peer_value", theirs},
                   {"ratio", lowerIsBetter ? theirs / ours : ours / theirs},
                   {"machine", device.empty() ? machineName() : device}};
  std::printf("%s\n", j.dump().c_str());
  std::fflush(stdout);
}

}  // namespace isoatlas::bench
