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
