// The demo: Colin27's T1 MRI (data/volumes/ch2.nii.gz, scripts/fetch-data), whose white matter
// `isoatlas run` segments from one seed in the centrum semiovale of each hemisphere, carves a ball
// out of, models and engraves. White matter reads about 110 there (isoatlas probe
// data/volumes/ch2.nii.gz --at 64,115,101 --radius 4), grey matter about 75. The benchmarks use the
// same seeds and parameters for their white-matter cases.
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>

#include "core/vec.h"
#include "core/volume.h"
#include "levelset/solver_backend.h"
#include "levelset/speed.h"

namespace isoatlas::pipeline {

inline constexpr const char* kDemoVolume = "data/volumes/ch2.nii.gz";
inline const levelset::SpeedParams kDemoParams{112, 14, 0.8f};
inline constexpr std::array<Vec3, 2> kDemoSeeds{{{64, 115, 101}, {116, 115, 101}}};  // voxel indices
inline constexpr double kDemoSeedRadius = 4;
// Each hemisphere's white matter a sphere (genus 0), as FreeSurfer's white surfaces: the two fronts
// meet at the corpus callosum and stay apart (Dice 0.998 to the free front's, which has genus 165).
inline constexpr levelset::Topology kDemoTopology = levelset::Topology::Preserve;
// The demo's edit: a ball carved out of the left hemisphere's white matter from its side, where the
// renders from the left see the crater.
inline constexpr const char* kDemoEdit = "sphere:-50,5,25,20";

// The demo's seeds apply to Colin27's T1 however its path is written: the file's name and its grid.
inline bool isDemoVolume(const std::string& path, const Volume& v) {
  return std::filesystem::path(path).filename() == std::filesystem::path(kDemoVolume).filename() &&
         v.dims == std::array<std::int64_t, 3>{181, 217, 181} && v.spacing.x == 1 && v.spacing.y == 1 && v.spacing.z == 1;
}

// Where the demo engraves its word: on the left hemisphere's lateral surface, within the surface's box
// (min, max), the stamp's centre and radius (the paper's Fig. 10).
struct DemoEngraving {
  Vec3 at;
  double radius;
};
inline DemoEngraving demoEngraving(const Vec3& boxMin, const Vec3& boxMax) {
  const Vec3 size = boxMax - boxMin;
  return {{boxMin.x, boxMin.y + 0.55 * size.y, boxMin.z + 0.6 * size.z}, 0.2 * size.y};
}

}  // namespace isoatlas::pipeline
