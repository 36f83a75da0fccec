// Parsing helpers shared by subcommands: balls "X,Y,Z[,R]", sizes "W,H", output files, numeric ranges
// and the edit steps.
#pragma once
#include <CLI/CLI.hpp>

#include <array>
#include <bit>
#include <memory>
#include <string>
#include <vector>

#include "core/mesh_io.h"
#include "core/numbers.h"
#include "core/vec.h"
#include "core/volume.h"
#include "core/volume_io.h"
#include "multires/base_mesh.h"
#include "pipeline/seed_ball.h"
#include "pipeline/volume_editing.h"

namespace isoatlas::app {

// "X,Y,Z" or "X,Y,Z,R" (R defaults to defaultRadius); throws Error naming `option` on bad text.
pipeline::Ball parseBall(const std::string& text, const std::string& option, double defaultRadius);
// "W,H": whole pixels from 1 to 8192; throws Error naming --size otherwise.
std::array<int, 2> parseSize(const std::string& text);
// An option that names a file to write: its folder must exist, known while parsing, before any work
// (exit 2, naming the option and the file). Folders an option makes (run's --output) take none.
CLI::Validator outputFile();

// A numeric option's range, declared with the option (`->check(inRange(0, 1))`): CLI11 refuses, while
// parsing and so before any work, a value outside [lo, hi], NaN, an infinity or text that is no
// number, with one line naming the option (exit 2). Every numeric option of the command has one; the
// help shows it, and tests/cli/options_test.cpp reads it back (the validator's name is "range").
CLI::Validator inRange(double lo, double hi);

// --backend's choices, checked while parsing (before a file is read or a GL context made).
CLI::Validator backendChoice();

// --topology free|preserve for the segmentation (levelset::Topology), checked while parsing; the help
// says what preserve keeps, and `defaults` what an empty choice means where it is not "free".
void addTopologyOption(CLI::App& sub, std::string& topology, const std::string& defaults = {});

// A ball's radius given inside X,Y,Z,R (--seed, probe --at) and probe's --radius, in voxels.
using pipeline::kMaxBallRadius;
using pipeline::kMinBallRadius;

// Ranges several subcommands share.
inline constexpr double kMaxIntensity = 1e12;  // |T|, eps and isovalues: past any scanner's values
inline constexpr double kMinWidth = 1e-6;      // eps must be > 0
inline constexpr double kMaxIterations = 100000;
inline constexpr double kMinSamples = 1000, kMaxSamples = 1e8;  // Hausdorff face samples per mesh
inline constexpr double kMaxLevel = 2 * std::countr_zero(multires::kMaxChartSize - 1);  // atlas::maxLevel of the finest charts
inline constexpr double kMaxMillimetres = 1e6;  // lengths in world mm (radii, depths, errors): a kilometre

// --volume N: which volume of a 4D NIfTI series the command reads (VolumeReadOptions), from 0.
void addVolumeReadOptions(CLI::App& sub, VolumeReadOptions& read);

// --space ras|lps: the frame of the mesh the command writes (MeshSpace, core/mesh_io.h), checked while
// parsing; meshSpace reads the choice.
void addMeshSpaceOption(CLI::App& sub, std::string& space);
MeshSpace meshSpace(const std::string& space);

// --union SHAPE and --subtract SHAPE on `sub`, each adding a step in command-line order.
void addEditStepOptions(CLI::App& sub, const std::shared_ptr<std::vector<pipeline::EditStep>>& steps);

}  // namespace isoatlas::app
