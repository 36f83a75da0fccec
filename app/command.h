// What every subcommand shares: --report, --quiet, and how a run ends. Each subcommand lives in its
// own file (app/<name>.cpp) and registers itself with addXCommand().
#pragma once
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <string>

namespace isoatlas::app {

struct CommonOptions {
  std::string report;  // --report FILE.json
  bool quiet = false;
  std::string maxMemory;  // --max-memory SIZE: the memory budget (core/memory_budget.h)
};

// A subcommand's work: fills `report` and returns the exit code (0, or 1 when the work failed).
using Action = std::function<int(nlohmann::json& report)>;

// Adds --report, --quiet and --max-memory to `sub` and makes it run `action` when chosen: errors become one line on
// stderr and exit 2 (bad input) or 1 (failure); the report is written on success. --report's folder
// must exist, unless it lies directly in `madeFolder` (run's -o): a folder the action makes once every
// input has been checked, so `run -o out/demo --report out/demo/r.json` works on a clean clone.
void bindAction(CLI::App& sub, const Action& action, int& exitCode, std::shared_ptr<const std::string> madeFolder = nullptr);

// Every subcommand, in the order --help lists them (main.cpp, and the tests that walk the options).
void addCommands(CLI::App& app, int& exitCode);

void writeJsonFile(const std::string& path, const nlohmann::json& json);

void addInfoCommand(CLI::App& app, int& exitCode);
void addRunCommand(CLI::App& app, int& exitCode);
void addProbeCommand(CLI::App& app, int& exitCode);
void addSegmentCommand(CLI::App& app, int& exitCode);
void addExtractCommand(CLI::App& app, int& exitCode);
void addBuildCommand(CLI::App& app, int& exitCode);
void addEvalCommand(CLI::App& app, int& exitCode);
void addEditDetailCommand(CLI::App& app, int& exitCode);
void addRenderCommand(CLI::App& app, int& exitCode);
void addEditCommand(CLI::App& app, int& exitCode);
void addViewCommand(CLI::App& app, int& exitCode);

}  // namespace isoatlas::app
