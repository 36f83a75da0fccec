// isoatlas run: the main job, volume to model, writing every product and an index.html into one
// folder. Stages that are not built yet are skipped and named as skipped; nothing is faked.
#include <chrono>
#include <filesystem>
#include <fstream>

#include "app/command.h"
#include "core/error.h"
#include "core/image.h"
#include "core/progress.h"
#include "core/volume_io.h"
#include "viewer/slice_render.h"

namespace isoatlas::app {
namespace {

// The embedded default: Colin27's T1 MRI, whose white matter the demo segments.
constexpr const char* kDefaultVolume = "data/volumes/ch2.nii.gz";

struct Stage {
  std::string name, status, detail;  // status: "done" or "skipped"
};

void writeIndexHtml(const std::filesystem::path& dir, const std::string& input, const std::vector<Stage>& stages,
                    const std::vector<std::pair<std::string, std::string>>& pictures) {
  std::ofstream html(dir / "index.html");
  html << "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>isoatlas run</title>\n"
       << "<style>body{font-family:sans-serif;max-width:1000px;margin:2em auto}td,th{padding:4px 10px;text-align:left}"
       << ".skipped{color:#999}img{max-width:100%}</style></head><body>\n"
       << "<h1>isoatlas run</h1>\n<p>Input: <code>" << input << "</code></p>\n<table>\n"
       << "<tr><th>stage</th><th>status</th><th>detail</th></tr>\n";
  for (const Stage& s : stages)
    html << "<tr class=\"" << s.status << "\"><td>" << s.name << "</td><td>" << s.status << "</td><td>" << s.detail
         << "</td></tr>\n";
  html << "</table>\n";
  for (const auto& [file, caption] : pictures)
    html << "<figure><img src=\"" << file << "\" alt=\"" << caption << "\"><figcaption>" << caption
         << "</figcaption></figure>\n";
  html << "<p>Figures: <a href=\"report.json\">report.json</a></p>\n</body></html>\n";
  if (!html) throw Error((dir / "index.html").string() + ": could not write", ErrorKind::Failure);
}

}  // namespace

void addRunCommand(CLI::App& app, int& exitCode) {
  auto* sub = app.add_subcommand("run", "the whole job on a volume: segment, extract, build, render (stages not built yet are skipped)");
  auto input = std::make_shared<std::string>(kDefaultVolume);
  auto outDir = std::make_shared<std::string>("out/demo");
  sub->add_option("volume", *input, "input volume")->capture_default_str();
  sub->add_option("-o,--output", *outDir, "folder for every product and index.html")->capture_default_str();
  bindAction(*sub, [input, outDir](nlohmann::json& r) {
    const auto start = std::chrono::steady_clock::now();
    const std::filesystem::path dir(*outDir);
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    require(!ec, *outDir + ": cannot create the output folder: " + ec.message());

    std::vector<Stage> stages;
    std::vector<std::pair<std::string, std::string>> pictures;
    logInfo("run: reading " + *input);
    const Volume volume = readVolume(*input);
    stages.push_back({"read", "done", std::to_string(volume.dims[0]) + " x " + std::to_string(volume.dims[1]) + " x " +
                                          std::to_string(volume.dims[2]) + " " + scalarTypeName(volume.type)});
    r["input"] = {{"file", *input}, {"dims", {volume.dims[0], volume.dims[1], volume.dims[2]}},
                  {"spacing", {volume.spacing.x, volume.spacing.y, volume.spacing.z}}};

    writePng((dir / "input_slices.png").string(), viewer::renderSlices(volume, viewer::volumeCentre(volume)));
    pictures.push_back({"input_slices.png", "the input: axial, coronal and sagittal slices through its centre"});
    stages.push_back({"render input slices", "done", "input_slices.png"});

    for (const char* pending : {"segment (issue 3)", "extract (issue 4)", "build multiresolution model (issue 5)",
                                "atlas", "render model"}) {
      stages.push_back({pending, "skipped", "stage not built yet"});
      logInfo(std::string("run: skipping ") + pending + ": stage not built yet");
    }
    r["stages"] = nlohmann::json::array();
    for (const Stage& s : stages) r["stages"].push_back({{"name", s.name}, {"status", s.status}, {"detail", s.detail}});
    r["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    writeJsonFile((dir / "report.json").string(), r);
    writeIndexHtml(dir, *input, stages, pictures);
    logInfo("run: wrote " + (dir / "index.html").string());
    return 0;
  }, exitCode);
}

}  // namespace isoatlas::app
