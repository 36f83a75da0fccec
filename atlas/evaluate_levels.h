// evaluateLevels: how close the model comes to the dense mesh at each uniform level: the mesh
// reconstructed at that level (reconstructLevel), measured by CGAL's Hausdorff distance both ways
// (core/distance/mesh_distance.h; the dense mesh's samples and tree made once for all levels), PSNR against the dense
// mesh's bounding-box diagonal from the largest distance and from the RMS distance.
//   base, atlas  the model
//   dense        the dense triangle mesh it was built from
//   levels       each within 0 .. maxLevel(chart size)
//   facePoints   Hausdorff face samples per mesh
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "atlas/atlas.h"
#include "core/distance/mesh_distance.h"
#include "core/image.h"
#include "core/mesh.h"
#include "multires/base_mesh.h"

namespace isoatlas::atlas {

struct LevelFigures {
  int level = 0;
  std::size_t vertices = 0, triangles = 0;
  double hausdorff = 0, psnrDb = 0;  // from the largest distance (the seed paper's measure)
  double rms = 0, psnrRmsDb = 0;      // from the root mean square distance (Multi-chart Geometry Images')
  bool closed = false, manifold = false;  // analyzeTopology's
};

// PSNR against level, one line per named model, as a picture a person reads (eval's --plot).
Image psnrPlot(const std::vector<std::pair<std::string, std::vector<LevelFigures>>>& models);

std::vector<LevelFigures> evaluateLevels(const multires::BaseMesh& base, const Atlas& atlas, const Mesh& dense,
                                         const std::vector<int>& levels, std::size_t facePoints = kHausdorffFacePoints);

}  // namespace isoatlas::atlas
