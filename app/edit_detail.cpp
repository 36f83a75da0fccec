// isoatlas edit-detail: fine detail stamped on a model (the paper's Fig. 10): an image or a word
// pressed into the surface at a point, written into detail charts of the tiles it reaches.
#include <filesystem>

#include "app/command.h"
#include "pipeline/model_building.h"
#include "app/options.h"
#include "atlas/reconstruct.h"
#include "atlas/stamp_detail.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/text.h"
#include "render/mesh_render.h"

namespace isoatlas::app {

void addEditDetailCommand(CLI::App& app, int& exitCode) {
  auto* sub = app.add_subcommand("edit-detail", "stamp fine detail (an image or a word) on a model's surface");
  auto model = std::make_shared<std::string>(), output = std::make_shared<std::string>(), at = std::make_shared<std::string>();
  auto render = std::make_shared<std::string>();
  auto request = std::make_shared<pipeline::StampRequest>();
  sub->add_option("model", *model, "the .isoatlas model")->required();
  sub->add_option("--stamp", request->image, "a PNG whose bright pixels are pressed in (grey or RGB)");
  sub->add_option("--text", request->text, "a word to engrave, rendered with --font");
  sub->add_option("--font", request->font, "a TrueType font for --text")->capture_default_str();
  sub->add_option("--at", *at, "X,Y,Z: a point at or near the surface (world mm); the stamp's centre is the nearest")->required();
  sub->add_option("--radius", request->radius, "the stamp's radius (mm)")->required()->check(inRange(1e-3, kMaxMillimetres));
  sub->add_option("--depth", request->depth, "how deep the ink is pressed (mm; negative raises it)")->required()->check(inRange(-kMaxMillimetres, kMaxMillimetres));
  sub->add_option("--detail", request->detailSize, "texels per side of the detail charts, 2^k + 1 above the chart size")
      ->capture_default_str()
      ->check(inRange(5, multires::kMaxChartSize));
  sub->add_option("-o,--output", *output, "the stamped model (.isoatlas)")->required()->check(outputFile());
  sub->add_option("--render", *render, "a close-up of the stamp at the finest level, as a PNG")->check(outputFile());
  bindAction(*sub, [=](nlohmann::json& r) {
    require(output->ends_with(".isoatlas"), *output + ": the stamped model must end in .isoatlas");
    require(render->empty() || render->ends_with(".png"), *render + ": --render writes a .png");
    pipeline::StampRequest req = *request;
    req.at = parsePoint(*at, "--at");
    atlas::Model m = atlas::readModel(*model);
    const atlas::StampStats s = pipeline::stampModel(m, req, r);
    pipeline::writeModelFiles(m, *output, {}, r);
    if (!render->empty()) {
      pipeline::Gpu gpu;  // the process's one context, for the render
      gpu.needGl();
      writePng(*render, pipeline::closeUp(m, s, req.radius));
      r["gl_contexts"] = gl::Context::made();
    }
    return 0;
  }, exitCode);
}

}  // namespace isoatlas::app
