#include "app/command.h"

#include "app/options.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/memory_budget.h"
#include "core/progress.h"

namespace isoatlas::app {

void writeJsonFile(const std::string& path, const nlohmann::json& json) {
  writeFileAtomically(path, json.dump(2) + "\n");
}

namespace {

// Whether `path` is a file directly in `folder`, by their absolute, normalised names.
bool liesIn(const std::string& path, const std::string& folder) {
  namespace fs = std::filesystem;
  return fs::absolute(path).lexically_normal().parent_path() == fs::absolute(fs::path(folder) / "").lexically_normal().parent_path();
}

}  // namespace

void bindAction(CLI::App& sub, const Action& action, int& exitCode, std::shared_ptr<const std::string> madeFolder) {
  auto common = std::make_shared<CommonOptions>();
  CLI::Option* report = sub.add_option("--report", common->report, "write the figures of this run as JSON");
  if (!madeFolder) report->check(outputFile());
  sub.add_flag("--quiet,-q", common->quiet, "no progress or informational lines on stderr");
  sub.add_option("--max-memory", common->maxMemory,
                 "the most memory one input may take once read (a volume's voxels, a model's charts), such as 8G; "
                 "default half the physical memory")
      ->check(CLI::Validator(
          [](std::string& text) {
            try {
              parseByteSize(text);
              return std::string();
            } catch (const Error& e) {
              return std::string(e.what());
            }
          },
          "SIZE"));
  sub.callback([&sub, action, common, &exitCode, madeFolder] {
    Progress::setQuiet(common->quiet);
    if (!common->maxMemory.empty()) setMemoryBudget(parseByteSize(common->maxMemory));
    nlohmann::json report;
    report["command"] = sub.get_name();
    try {
      if (madeFolder && !common->report.empty() && !liesIn(common->report, *madeFolder))
        requireOutputFolder(common->report);  // as the option's check would, now that -o is known
      exitCode = action(report);
      if (!common->report.empty()) writeJsonFile(common->report, report);
    } catch (const Error& e) {
      std::fprintf(stderr, "isoatlas %s: %s\n", sub.get_name().c_str(), e.what());
      exitCode = e.exitCode();
    } catch (const std::bad_alloc&) {
      std::fprintf(stderr, "isoatlas %s: out of memory\n", sub.get_name().c_str());
      exitCode = 1;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "isoatlas %s: internal error: %s\n", sub.get_name().c_str(), e.what());
      exitCode = 1;
    }
  });
}

void addCommands(CLI::App& app, int& exitCode) {
  addInfoCommand(app, exitCode);
  addProbeCommand(app, exitCode);
  addSegmentCommand(app, exitCode);
  addEditCommand(app, exitCode);
  addExtractCommand(app, exitCode);
  addBuildCommand(app, exitCode);
  addEvalCommand(app, exitCode);
  addEditDetailCommand(app, exitCode);
  addRenderCommand(app, exitCode);
  addViewCommand(app, exitCode);
  addRunCommand(app, exitCode);
}

}  // namespace isoatlas::app
