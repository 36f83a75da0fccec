// Data the benchmarks derive once from data/ and keep in data/derived/: the white-matter level set
// of ch2better.nii.gz (301 x 370 x 316, 0.5 mm), segmented by isoatlas's CPU solver from the demo's
// seeds (minutes on 2 cores the first time).
#pragma once
#include <cstdio>
#include <filesystem>
#include <string>

#include "core/volume_io.h"
#include "levelset/level_set.h"

namespace isoatlas::bench {

inline Volume ch2betterWhiteMatterPhi(const std::string& data) {
  const std::string phiPath = data + "/derived/ch2better_white_matter_phi.nii.gz";
  if (!std::filesystem::exists(phiPath)) {
    std::fprintf(stderr, "bench: segmenting ch2better's white matter once (kept in %s)\n", phiPath.c_str());
    const Volume v = readVolume(data + "/volumes/ch2better.nii.gz");
    levelset::LevelSet ls(v, {112, 14, 0.8f});
    ls.addSphere({98, 194, 199}, 8);  // the demo's seeds, mapped through world coordinates
    ls.addSphere({202, 194, 199}, 8);
    ls.run({.maxIterations = 4000});
    std::filesystem::create_directories(data + "/derived");
    writeVolume(phiPath, ls.phi());
  }
  return readVolume(phiPath);
}

}  // namespace isoatlas::bench
