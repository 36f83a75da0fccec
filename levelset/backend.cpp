#include "levelset/backend.h"

#include <algorithm>

#include "core/error.h"

namespace isoatlas::levelset {

void requireBackendChoice(const std::string& choice) {
  require(std::find(kBackendChoices.begin(), kBackendChoices.end(), choice) != kBackendChoices.end(),
          "--backend " + choice + ": expected gpu, cpu or auto");
}

Backend backendFor(const std::string& choice, bool softwareGl) {
  requireBackendChoice(choice);
  return choice == "gpu" || (choice == "auto" && !softwareGl) ? Backend::Gpu : Backend::Cpu;
}

}  // namespace isoatlas::levelset
