// isoatlas edit-detail: fine detail stamped on a model (the paper's Fig. 10): an image or a word
// pressed into the surface at a point, written into detail charts of the tiles it reaches.
#include <filesystem>

#include "app/command.h"
#include "app/model_building.h"
#include "app/options.h"
#include "atlas/reconstruct.h"
#include "atlas/stamp_detail.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/text.h"
#include "viewer/mesh_render.h"

namespace isoatlas::app {

Image closeUp(const atlas::Model& model, const atlas::StampStats& stamp, double radius) {
  const Mesh finest = atlas::reconstructLevel(model.base, model.atlas, atlas::maxLevel(model.atlas));
  const Mesh near = selectFaces(finest, [&](std::size_t f) {
    const auto c = finest.face(f);
    return norm(finest.positions[c[0]] - stamp.centre) < 1.3 * radius;
  });
  const Vec3 worldUp = std::abs(stamp.normal.z) > 0.9 ? Vec3{0, 1, 0} : Vec3{0, 0, 1};
  // selectFaces keeps the normals of the vertices it keeps: the atlas's, stamped.
  return viewer::renderMesh(near, {.viewDirection = stamp.normal * -1, .up = worldUp});
}

atlas::StampStats stampModel(atlas::Model& model, const StampRequest& request, nlohmann::json& r) {
  require(!request.image.empty() || !request.text.empty(), "give --stamp IMAGE.png or --text WORD");
  require(request.image.empty() || request.text.empty(), "give --stamp or --text, not both");
  atlas::Stamp stamp;
  stamp.image = request.image.empty() ? renderText(request.text, 128, request.font) : readPng(request.image);
  stamp.at = request.at;
  stamp.radius = request.radius;
  stamp.depth = request.depth;
  stamp.detailSize = request.detailSize;
  const atlas::StampStats s = atlas::stampDetail(model.base, model.atlas, stamp);
  require(s.texelsChanged + s.detailTexelsChanged > 0, "the stamp reaches no part of the surface (its image is blank there?)");
  r["centre"] = {s.centre.x, s.centre.y, s.centre.z};
  r["normal"] = {s.normal.x, s.normal.y, s.normal.z};
  r["detail_tiles"] = s.detailTiles;
  r["texels_changed"] = s.texelsChanged;
  r["detail_texels_changed"] = s.detailTexelsChanged;
  r["detail_charts"] = model.atlas.details.size();
  r["max_level"] = atlas::maxLevel(model.atlas);
  logInfo("edit-detail: stamped " + std::to_string(s.detailTiles) + " tiles' detail charts and " + std::to_string(s.texelsChanged) +
          " texels of their charts");
  return s;
}

void addEditDetailCommand(CLI::App& app, int& exitCode) {
  auto* sub = app.add_subcommand("edit-detail", "stamp fine detail (an image or a word) on a model's surface");
  auto model = std::make_shared<std::string>(), output = std::make_shared<std::string>(), at = std::make_shared<std::string>();
  auto render = std::make_shared<std::string>();
  auto request = std::make_shared<StampRequest>();
  sub->add_option("model", *model, "the .isoatlas model")->required();
  sub->add_option("--stamp", request->image, "a PNG whose bright pixels are pressed in (grey or RGB)");
  sub->add_option("--text", request->text, "a word to engrave, rendered with --font");
  sub->add_option("--font", request->font, "a TrueType font for --text")->capture_default_str();
  sub->add_option("--at", *at, "X,Y,Z: a point at or near the surface (world mm); the stamp's centre is the nearest")->required();
  sub->add_option("--radius", request->radius, "the stamp's radius (mm)")->required();
  sub->add_option("--depth", request->depth, "how deep the ink is pressed (mm; negative raises it)")->required();
  sub->add_option("--detail", request->detailSize, "texels per side of the detail charts, 2^k + 1 above the chart size")
      ->capture_default_str();
  sub->add_option("-o,--output", *output, "the stamped model (.isoatlas)")->required();
  sub->add_option("--render", *render, "a close-up of the stamp at the finest level, as a PNG");
  bindAction(*sub, [=](nlohmann::json& r) {
    require(output->ends_with(".isoatlas"), *output + ": the stamped model must end in .isoatlas");
    require(render->empty() || render->ends_with(".png"), *render + ": --render writes a .png");
    StampRequest req = *request;
    req.at = parsePoint(*at, "--at");
    atlas::Model m = atlas::readModel(*model);
    const atlas::StampStats s = stampModel(m, req, r);
    writeModelFiles(m, *output, "", r);
    if (!render->empty()) {
      Gpu gpu;  // the process's one context, for the render
      gpu.needGl();
      writePng(*render, closeUp(m, s, req.radius));
      r["gl_contexts"] = gl::Context::made();
    }
    return 0;
  }, exitCode);
}

}  // namespace isoatlas::app
