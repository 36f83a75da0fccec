#include "core/memory_budget.h"

#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "core/error.h"

namespace isoatlas {
namespace {

std::uint64_t halfThePhysicalMemory() {
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || size <= 0) return std::uint64_t(8) << 30;  // unknown: what earlier versions allowed
  return std::uint64_t(pages) * std::uint64_t(size) / 2;
}

std::atomic<std::uint64_t>& budget() {
  static std::atomic<std::uint64_t> bytes{halfThePhysicalMemory()};
  return bytes;
}

// "512 KiB", "1.5 MiB", "12 GiB": the largest unit that keeps a whole number, a tenth below ten.
std::string sizeText(std::uint64_t bytes) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB"};
  double value = double(bytes);
  int unit = 0;
  while (value >= 1024 && unit < 5) value /= 1024, ++unit;
  char text[64];
  std::snprintf(text, sizeof text, unit > 0 && value < 10 ? "%.1f %s" : "%.0f %s", value, units[unit]);
  std::string s = text;
  if (const std::size_t dot = s.find(".0 "); dot != std::string::npos) s.erase(dot, 2);
  return s;
}

}  // namespace

std::uint64_t memoryBudget() { return budget().load(std::memory_order_relaxed); }
void setMemoryBudget(std::uint64_t bytes) { budget().store(bytes, std::memory_order_relaxed); }

void requireWithinMemoryBudget(std::uint64_t bytes, const std::string& what) {
  if (bytes > memoryBudget())
    throw Error(what + " would take " + sizeText(bytes) + ", more than the memory budget of " + sizeText(memoryBudget()) +
                " (--max-memory)");
}

std::uint64_t parseByteSize(const std::string& text) {
  const auto bad = [&] { return Error("'" + text + "' is not a size in bytes (such as 8G, 512M or 1000000)"); };
  std::size_t end = 0;
  double value = 0;
  try {
    value = std::stod(text, &end);
  } catch (const std::exception&) {
    throw bad();
  }
  double unit = 1;
  if (end + 1 == text.size()) {
    switch (std::toupper(static_cast<unsigned char>(text[end]))) {
      case 'K': unit = 1024.0; break;
      case 'M': unit = 1024.0 * 1024; break;
      case 'G': unit = 1024.0 * 1024 * 1024; break;
      case 'T': unit = 1024.0 * 1024 * 1024 * 1024; break;
      default: throw bad();
    }
  } else if (end != text.size()) {
    throw bad();
  }
  const double bytes = value * unit;
  if (!std::isfinite(bytes) || bytes < 1 || bytes >= 1.8e19) throw bad();
  return std::uint64_t(bytes);
}

}  // namespace isoatlas
