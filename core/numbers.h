// Numbers as users type them on a command line or in a script: "A,B,C..." comma-separated, finite.
#pragma once
#include <string>
#include <vector>

#include "core/vec.h"

namespace isoatlas {

// Throws Error naming `option` (the option or the file and line) and `expected` on bad text.
std::vector<double> parseNumbers(const std::string& text, const std::string& option, const char* expected);
// "X,Y,Z"; throws Error naming `option` on bad text.
Vec3 parsePoint(const std::string& text, const std::string& option);
// x as a message shows it: printf's %g (6 significant digits, no trailing zeros).
std::string shortNumber(double x);

}  // namespace isoatlas
