#include "app/run_engraving.h"

#include <algorithm>
#include <chrono>

#include "core/error.h"
#include "core/image.h"
#include "core/progress.h"
#include "multires/base_mesh.h"
#include "pipeline/demo.h"
#include "pipeline/model_building.h"

namespace isoatlas::app {
namespace {
constexpr const char* kEngraveStage = "engrave a word (fine detail, beside the render)";
constexpr const char* kEngravedModel = "model_engraved.isoatlas";
}  // namespace

std::future<Engraving> startEngraving(const atlas::Model& model, const Mesh& surface, const std::filesystem::path& dir) {
  return std::async(std::launch::async, [&model, &surface, dir] {
    const auto start = std::chrono::steady_clock::now();
    const Box box = boundingBox(surface.positions);
    const pipeline::DemoEngraving place = pipeline::demoEngraving(box.min, box.max);
    const pipeline::StampRequest engrave{.text = "isoatlas", .at = place.at, .radius = place.radius, .depth = 1.5,
                                         .detailSize = std::min(multires::kMaxChartSize, 4 * (model.chartSize - 1) + 1)};
    Engraving e{.radius = engrave.radius};
    if (engrave.detailSize <= model.chartSize) {
      e.skipped = "the charts are already the finest (--chart 129)";
      return e;
    }
    try {
      atlas::Model& engraved = e.model.emplace(model);
      e.stamped = pipeline::stampModel(engraved, engrave, e.figures);
      pipeline::writeModelFiles(engraved, (dir / kEngravedModel).string(), {}, e.figures);
    } catch (const Error& error) {
      e.model.reset();
      e.skipped = error.what();
      e.failed = true;
    }
    e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return e;
  });
}

void finishEngraving(RunJob& job, std::future<Engraving>& engraving) {
  Engraving e = engraving.get();
  if (!e.model) {
    job.skipped(kEngraveStage, e.skipped);
    if (e.failed) logInfo("run: skipping the engraving: " + e.skipped);
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  job.report["engrave"] = std::move(e.figures);
  job.products.add(kEngravedModel, "the model with \"isoatlas\" engraved in detail charts (isoatlas edit-detail)");
  try {
    writePng(job.products.add("engraved.png", "the engraved word at the model's finest level, close up", true),
             pipeline::closeUp(*e.model, e.stamped, e.radius));
  } catch (const Error& error) {
    job.skipped(kEngraveStage, error.what());
    logInfo(std::string("run: skipping the engraving's close-up: ") + error.what());
    return;
  }
  job.stages.push_back({kEngraveStage, "done", std::to_string(e.stamped.detailTiles) + " tiles given detail charts: " + kEngravedModel,
                        e.seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
}

}  // namespace isoatlas::app
