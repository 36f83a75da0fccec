#include "core/numbers.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "core/error.h"

namespace isoatlas {

std::string shortNumber(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

std::vector<double> parseNumbers(const std::string& text, const std::string& option, const char* expected) {
  std::vector<double> numbers;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ',')) {
    char* end = nullptr;
    const double v = std::strtod(part.c_str(), &end);
    if (part.empty() || *end != '\0' || !std::isfinite(v))
      throw Error(option + " " + text + ": \"" + part + "\" is not a number (expected " + expected + ")");
    numbers.push_back(v);
  }
  return numbers;
}

Vec3 parsePoint(const std::string& text, const std::string& option) {
  const std::vector<double> numbers = parseNumbers(text, option, "X,Y,Z");
  if (numbers.size() != 3) throw Error(option + " " + text + ": expected X,Y,Z");
  return {numbers[0], numbers[1], numbers[2]};
}

}  // namespace isoatlas
