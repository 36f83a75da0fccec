// Parsing helpers shared by subcommands: balls "X,Y,Z[,R]", sizes "W,H", output files and the edit steps.
#pragma once
#include <CLI/CLI.hpp>

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/numbers.h"
#include "core/vec.h"
#include "core/volume.h"
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

// --union SHAPE and --subtract SHAPE on `sub`, each adding a step in command-line order.
void addEditStepOptions(CLI::App& sub, const std::shared_ptr<std::vector<pipeline::EditStep>>& steps);

}  // namespace isoatlas::app
