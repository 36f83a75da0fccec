// Data the benchmarks derive once from data/ and keep in data/derived/: the white-matter level set
// of ch2better.nii.gz (301 x 370 x 316, 0.5 mm), segmented by isoatlas's CPU solver from the demo's
// seeds (minutes on 2 cores the first time), and the demo's white-matter surface of ch2.nii.gz.
#pragma once
#include <cstdio>
#include <filesystem>
#include <string>

#include "core/mesh_io.h"
#include "core/volume_io.h"
#include "extract/extract_surface.h"
#include "levelset/level_set.h"
#include "pipeline/demo.h"

namespace isoatlas::bench {

inline Volume ch2betterWhiteMatterPhi(const std::string& data) {
  const std::string phiPath = data + "/derived/ch2better_white_matter_phi.nii.gz";
  if (!std::filesystem::exists(phiPath)) {
    std::fprintf(stderr, "bench: segmenting ch2better's white matter once (kept in %s)\n", phiPath.c_str());
    const Volume v = readVolume(data + "/volumes/ch2better.nii.gz");
    levelset::LevelSet ls(v, pipeline::kDemoParams, {.settledChange = 0});  // every page every iteration, as recorded
    ls.addSphere({98, 194, 199}, 8);  // the demo's seeds, mapped through world coordinates
    ls.addSphere({202, 194, 199}, 8);
    ls.run({.maxIterations = 4000, .changedShare = 0});  // the criterion the recorded figures were made with
    std::filesystem::create_directories(data + "/derived");
    writeVolume(phiPath, ls.phi());
  }
  return readVolume(phiPath);
}

// The demo's surface: ch2.nii.gz's white matter segmented from the demo's seeds (as `isoatlas run`
// does), extracted from the level set's pages, largest component; kept in data/derived/.
inline Mesh ch2WhiteMatterSurface(const std::string& data) {
  const std::string path = data + "/derived/ch2_white_matter.ply";
  if (!std::filesystem::exists(path)) {
    std::fprintf(stderr, "bench: segmenting ch2's white matter once (kept in %s)\n", path.c_str());
    levelset::LevelSet ls(readVolume(data + "/volumes/ch2.nii.gz"), pipeline::kDemoParams, {.settledChange = 0});  // as recorded
    for (const Vec3& seed : pipeline::kDemoSeeds) ls.addSphere(seed, pipeline::kDemoSeedRadius);
    ls.run({.maxIterations = 3000, .changedShare = 0});  // the criterion the recorded figures were made with
    std::filesystem::create_directories(data + "/derived");
    writeMesh(path, extract::extractLevelSet(ls, {.largestComponents = 1}));
  }
  return readMesh(path);
}

}  // namespace isoatlas::bench
