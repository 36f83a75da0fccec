// run's stages, each timed into the job: segment, edit, extract, the pictures, the model's build and
// its levels' accuracy. Each writes its products into the run's folder and its figures into the report.
#pragma once
#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "atlas/evaluate_levels.h"
#include "atlas/model_file.h"
#include "core/mesh.h"
#include "core/mesh_io.h"
#include "core/volume.h"
#include "edit/dvt/volume_tree.h"
#include "edit/solids/solid.h"
#include "pipeline/gpu.h"
#include "pipeline/model_building.h"
#include "pipeline/run_page.h"
#include "pipeline/segmentation.h"
#include "pipeline/volume_editing.h"

namespace isoatlas::app {

// One run: its input, the process's GL context, what it wrote and the stages it went through (each
// with its seconds), and the report they fill.
struct RunJob {
  std::string input;
  Volume volume;
  pipeline::Gpu gpu;
  pipeline::RunProducts products;
  std::vector<pipeline::RunStage> stages;
  nlohmann::json& report;

  // Runs one stage, timed; `work` returns its detail line.
  void stage(const std::string& name, const std::function<std::string()>& work) {
    const auto start = std::chrono::steady_clock::now();
    std::string detail = work();
    stages.push_back({name, "done", std::move(detail), std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
  }
  void skipped(const std::string& name, const std::string& why) { stages.push_back({name, "skipped", why}); }
};

// The segmentation's seeds and parameters: the user's (--seed, --target, --width, --alpha), or the
// demo's when the input is the demo volume and no seed is given (then the demo's edit too, unless
// the user gave edits).
struct SegmentationSetup {
  std::vector<pipeline::Ball> seeds;
  levelset::SpeedParams params;
  pipeline::EditRequest edits;
  levelset::Topology topology;
};

// Segments the volume (mask.nii.gz, phi.nii.gz, view-session.txt).
pipeline::Segmentation segmentStage(RunJob& job, const SegmentationSetup& setup, int iterations, bool halfResolutionStart);

// The edits on a volume tree of the level set's phi (read from its pages). Its picture waits for
// surfacePictures, which runs beside the model's build.
struct EditedVolume {
  std::optional<pipeline::EditedTree> edited;
  std::optional<edit::dvt::VolumeTree> tree;  // edited->tree's streams, taken once
};
EditedVolume editStage(RunJob& job, const pipeline::Segmentation& s, const pipeline::EditRequest& edits,
                       const std::vector<std::unique_ptr<edit::dvt::DistanceSolid>>& solids);

// Marching cubes over the edited tree's distances; without edits, over the level set's active pages,
// read where the solver keeps them. The surface keeps its largest component; with the topology
// preserved, its `seeds` largest (one per seed).
// The files are written in `space` (--space); the surface returned stays in RAS.
Mesh extractStage(RunJob& job, const pipeline::Segmentation& s, const EditedVolume& edit, std::size_t seeds, MeshSpace space);

// The edited tree ray cast (the edit's picture), then the surface seen from the left (RAS -x) and
// from above, as a reader of an atlas would look, and the segmentation over the input through the
// first seed (so the slices cut the structure). Returns the pictures' names.
std::string surfacePictures(RunJob& job, const EditedVolume& edit, const Mesh& surface, const pipeline::Segmentation& s,
                            const Vec3& firstSeed);

// The multiresolution model of the surface (base mesh, atlas), its files and previews, made on a
// thread of its own beside the pictures (so nothing here touches GL or the job): what it wrote is in
// `products`, its figures in `figures`.
struct BuiltModel {
  std::optional<atlas::Model> model;
  nlohmann::json figures;
  pipeline::RunProducts products;
  double seconds = 0;
};
BuiltModel buildModelFiles(const Mesh& surface, const pipeline::ModelRequest& request, const std::filesystem::path& dir);

// The model's accuracy per level (eval's figures) and its plot, on the same thread.
struct MeasuredLevels {
  std::vector<atlas::LevelFigures> levels;
  pipeline::RunProducts products;
  double seconds = 0;
};
MeasuredLevels measureLevels(const atlas::Model& model, const Mesh& surface, const std::vector<int>& levels, std::size_t facePoints,
                             const std::filesystem::path& dir);

void addProducts(RunJob& job, const pipeline::RunProducts& products);

// The built model into the job, with its picture at level 4 (drawn here, where the GL context is);
// the stage's seconds are the build's and the picture's.
void modelStage(RunJob& job, BuiltModel& built, std::uint32_t chartSize);

// The levels' figures into the job (eval's, in report.json's model).
void levelsStage(RunJob& job, const MeasuredLevels& measured);

}  // namespace isoatlas::app
