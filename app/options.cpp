#include "app/options.h"

#include "core/atomic_file.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "core/progress.h"
#include "levelset/backend.h"

namespace isoatlas::app {

namespace {

// "in [lo, hi]", as inRange's help and messages and parseBall's message give a range: %g keeps it short
// (1e+06 rather than 1000000.000000), and tests/cli/options_test.cpp parses it back.
std::string rangeText(double lo, double hi) {
  char text[64];
  std::snprintf(text, sizeof text, "in [%g, %g]", lo, hi);
  return text;
}

}  // namespace

std::array<int, 2> parseSize(const std::string& text) {
  const std::vector<double> v = parseNumbers(text, "--size", "W,H");
  require(v.size() == 2 && v[0] == std::floor(v[0]) && v[1] == std::floor(v[1]) && v[0] >= 1 && v[1] >= 1 && v[0] <= 8192 && v[1] <= 8192,
          "--size " + text + ": expected W,H, whole pixels from 1 to 8192");
  return {int(v[0]), int(v[1])};
}

pipeline::Ball parseBall(const std::string& text, const std::string& option, double defaultRadius) {
  const std::vector<double> numbers = parseNumbers(text, option, "X,Y,Z or X,Y,Z,R");
  if (numbers.size() != 3 && numbers.size() != 4) throw Error(option + " " + text + ": expected X,Y,Z or X,Y,Z,R");
  const double radius = numbers.size() == 4 ? numbers[3] : defaultRadius;
  if (!(radius >= kMinBallRadius && radius <= kMaxBallRadius))
    throw Error(option + " " + text + ": the radius must lie " + rangeText(kMinBallRadius, kMaxBallRadius) + " voxels");
  return {{numbers[0], numbers[1], numbers[2]}, radius};
}

CLI::Validator outputFile() {
  return CLI::Validator(
      [](std::string& path) {
        try {
          requireOutputFolder(path);
        } catch (const Error& e) {
          return std::string(e.what());
        }
        return std::string();
      },
      "FILE");
}

CLI::Validator backendChoice() {
  return CLI::IsMember(std::vector<std::string>(levelset::kBackendChoices.begin(), levelset::kBackendChoices.end()));
}

void addTopologyOption(CLI::App& sub, std::string& topology, const std::string& defaults) {
  auto* option = sub.add_option("--topology", topology,
                                "free, or preserve: the model keeps the seeds' topology (one sphere per seed, no handles or cavities; "
                                "Han, Xu and Prince's level set)" + defaults);
  if (defaults.empty()) option->capture_default_str();
  option->check(CLI::IsMember(std::vector<std::string>(levelset::kTopologyChoices.begin(), levelset::kTopologyChoices.end())));
}

void addMeshSpaceOption(CLI::App& sub, std::string& space) {
  sub.add_option("--space", space, "the mesh's frame: ras (isoatlas's, nibabel's) or lps (ITK's, and what 3D Slicer assumes for an untagged PLY or OBJ)")
      ->capture_default_str()
      ->check(CLI::IsMember({"ras", "lps"}));
}

MeshSpace meshSpace(const std::string& space) { return parseMeshSpace(space, "--space"); }

void addVolumeReadOptions(CLI::App& sub, VolumeReadOptions& read) {
  sub.add_option("--volume", read.volume, "which volume of a 4D series (fMRI, diffusion) to read (0: the first; a 4D file needs it, a 3D file is volume 0)")
      ->check(inRange(0, 1e6));
  sub.add_option("--series", read.series, "which DICOM series of a folder to read, by its SeriesInstanceUID (a folder of several needs it)");
}

CLI::Validator inRange(double lo, double hi) {
  const std::string range = rangeText(lo, hi);
  return CLI::Validator(
      [lo, hi, text = range](std::string& value) {
        char* end = nullptr;
        errno = 0;
        const double v = std::strtod(value.c_str(), &end);
        if (value.empty() || end != value.c_str() + value.size() || errno == ERANGE || !std::isfinite(v))
          return "'" + value + "' is not a finite number";
        if (v < lo || v > hi) return "'" + value + "' is not " + text;
        return std::string();
      },
      range, "range");
}

void addEditStepOptions(CLI::App& sub, const std::shared_ptr<std::vector<pipeline::EditStep>>& steps) {
  const std::string shapes =
      "SHAPE in world coordinates: sphere:X,Y,Z,R  box:X0,Y0,Z0,X1,Y1,Z1  capsule:X0,Y0,Z0,X1,Y1,Z1,R  torus:X,Y,Z,R,r  mesh:FILE";
  // Callbacks as each option is parsed, so unions and subtractions keep the command line's order.
  sub.add_option_function<std::string>("--union", [steps](const std::string& s) { steps->push_back({edit::dvt::Op::Union, s}); },
                                       "add a " + shapes + "; repeatable")
      ->trigger_on_parse();
  sub.add_option_function<std::string>("--subtract", [steps](const std::string& s) { steps->push_back({edit::dvt::Op::Subtract, s}); },
                                       "carve a SHAPE out; repeatable, applied in order with --union")
      ->trigger_on_parse();
}

}  // namespace isoatlas::app
