// Parsing helpers shared by subcommands: points "X,Y,Z[,R]" and the --backend choice.
#pragma once
#include <string>

#include "core/vec.h"
#include "core/volume.h"
#include "levelset/level_set.h"

namespace isoatlas::app {

struct Ball {
  Vec3 centre;
  double radius;
};
// "X,Y,Z" or "X,Y,Z,R" (R defaults to defaultRadius); throws Error naming `option` on bad text.
Ball parseBall(const std::string& text, const std::string& option, double defaultRadius);
// Throws Error unless the voxel index lies inside the volume.
void requireInside(const Volume& v, const Vec3& index, const std::string& what);

// "gpu", "cpu" or "auto": auto takes the GPU when one is there, and the CPU backend (with a line
// saying so) when the only GL is a software rasteriser. Returns the backend and the renderer's name.
levelset::Backend chooseBackend(const std::string& choice, std::string& renderer);

}  // namespace isoatlas::app
