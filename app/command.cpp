#include "app/command.h"

#include "app/options.h"

#include <cstdio>
#include <fstream>
#include <memory>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"

namespace isoatlas::app {

void writeJsonFile(const std::string& path, const nlohmann::json& json) {
  writeFileAtomically(path, json.dump(2) + "\n");
}

void bindAction(CLI::App& sub, const Action& action, int& exitCode) {
  auto common = std::make_shared<CommonOptions>();
  sub.add_option("--report", common->report, "write the figures of this run as JSON")->check(outputFile());
  sub.add_flag("--quiet,-q", common->quiet, "no progress or informational lines on stderr");
  sub.callback([&sub, action, common, &exitCode] {
    Progress::setQuiet(common->quiet);
    nlohmann::json report;
    report["command"] = sub.get_name();
    try {
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

}  // namespace isoatlas::app
