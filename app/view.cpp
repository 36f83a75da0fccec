// isoatlas view: the window (viewer/app/viewer_app.h).
#include "app/command.h"
#include "viewer/app/viewer_app.h"

namespace isoatlas::app {

void addViewCommand(CLI::App& app, int& exitCode) {
  auto* sub = app.add_subcommand("view", "a window showing a model, a volume tree or a volume (needs a display)");
  auto o = std::make_shared<viewer::ViewerOptions>();
  sub->add_option("file", o->files, "a model (.isoatlas), a volume tree (.dvt) or a volume")->required();
  sub->add_option("--frames", o->frames, "draw this many frames and close (0: until the window is closed)")->capture_default_str();
  sub->add_option("--screenshot", o->screenshot, "with --frames: save the last frame as this PNG");
  bindAction(*sub, [o](nlohmann::json& r) {
    viewer::runViewer(*o);
    r["frames"] = o->frames;
    if (!o->screenshot.empty()) r["screenshot"] = o->screenshot;
    return 0;
  }, exitCode);
}

}  // namespace isoatlas::app
