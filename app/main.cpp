// isoatlas: from a 3D scan to a surface you can edit and render at any level of detail.
#include <oneapi/tbb/global_control.h>

#include <cstdio>
#include <new>

#include "app/command.h"

int main(int argc, char** argv) {
  using namespace isoatlas::app;
  CLI::App app{"isoatlas: segment a volume, extract its surface, and build a multiresolution atlas of it"};
  app.set_version_flag("--version", "isoatlas 0.1.0");
  app.require_subcommand(1);
  int exitCode = 0;
  // TBB's worker threads are joined before the process exits (below), so that nothing of ours runs
  // while exit handlers do: LeakSanitizer's tracer crashed now and then on threads still alive then.
  oneapi::tbb::task_scheduler_handle workers{oneapi::tbb::attach{}};

  addCommands(app, exitCode);

  if (argc > 1 && argv[1][0] != '-') {
    bool known = false;
    for (const CLI::App* sub : app.get_subcommands({})) known |= sub->get_name() == argv[1];
    if (!known) {
      std::fprintf(stderr, "isoatlas: unknown subcommand '%s' (see isoatlas --help)\n", argv[1]);
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "isoatlas: %s (see isoatlas --help)\n", e.what());
    return 2;
  }
  oneapi::tbb::finalize(workers, std::nothrow);
  return exitCode;
}
