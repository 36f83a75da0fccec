// isoatlas view: the window (viewer/viewer_app.h), building models with `build`'s stage.
#include "app/command.h"

#include <algorithm>

#include "pipeline/model_building.h"
#include "app/options.h"
#include "core/error.h"
#include "viewer/viewer_app.h"

namespace isoatlas::app {

void addViewCommand(CLI::App& app, int& exitCode) {
  auto* sub = app.add_subcommand("view", "a window to segment a volume, edit it and inspect models and volume trees (needs a display)");
  auto o = std::make_shared<viewer::ViewerOptions>();
  sub->add_option("files", o->files, "volumes (to segment), models (.isoatlas) and volume trees (.dvt), opened in turn");
  addVolumeReadOptions(*sub, o->read);
  sub->add_option("--script", o->script, "replay the actions in this text file (docs/view-script.md)");
  sub->add_option("--frames", o->frames, "draw this many frames and close (0: until the window is closed)")
      ->capture_default_str()
      ->check(inRange(0, 1e7));
  sub->add_option("--screenshot", o->screenshot, "with --frames: save the last frame as this PNG")->check(outputFile());
  sub->add_option("--backend", o->backend, "the segmentation's solver: gpu, cpu or auto (the CPU where GL is a software rasteriser)")
      ->capture_default_str()
      ->check(backendChoice());
  auto size = std::make_shared<std::string>("1280,800");
  sub->add_option("--size", *size, "W,H: the window's size in pixels")->capture_default_str();
  // The model is built as `build` builds it (its defaults), on a worker thread.
  o->buildModel = [](const Mesh& surface) {
    nlohmann::json figures;
    return pipeline::buildModel(pipeline::prepareModelInput(surface), pipeline::ModelRequest{}, figures);
  };
  bindAction(*sub, [o, size](nlohmann::json& r) {
    require(o->screenshot.empty() || o->frames > 0, "--screenshot saves the last of --frames N: give --frames too");
    const auto [width, height] = parseSize(*size);
    o->width = width, o->height = height;
    const viewer::ViewerReport v = viewer::runViewer(*o);
    r["frames"] = nlohmann::json::object();
    for (const auto& [mode, f] : v.modes) r["frames"][mode] = {{"frames", f.frames}, {"mean_ms", f.meanMs}, {"max_ms", f.maxMs}};
    r["iterations"] = v.iterations;
    if (!v.backend.empty()) r["backend"] = v.backend;
    r["status"] = v.status;
    if (!v.treeDabMs.empty()) {  // the tree brush's latency, each dab's write to its picture
      std::vector<double> ms = v.treeDabMs;
      std::sort(ms.begin(), ms.end());
      r["tree_dabs"] = {{"dabs", ms.size()}, {"median_ms", ms[ms.size() / 2]}, {"max_ms", ms.back()}};
    }
    if (!o->screenshot.empty()) r["screenshot"] = o->screenshot;
    return 0;
  }, exitCode);
}

}  // namespace isoatlas::app
