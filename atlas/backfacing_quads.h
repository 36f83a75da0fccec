// The texel quads of an atlas's charts that turn against the surface as the finest level draws
// them. Each quad is cut into two triangles as squareTriangles cuts it (the reconstruction eval
// writes, and the CPU stage of the renderer); a quad counts when either triangle's normal points
// against the surface. Two measures, by which normals:
//   - folded (countFoldedQuads): against the normal of the dense face under the triangle's centroid
//     in the chart (Atlas::triangleFaceNormals): the drawn surface faces the other way from the
//     surface it samples, a fold of the model: a hole under back-face culling, a dark line under
//     two-sided shading.
//   - backfacing (countBackFacingQuads): against the atlas's normals at its corners (their sum), the
//     shading normals (interpolated vertex normals). Most folds, and also triangles lying in a dense face
//     whose own normal points against its vertices' (a small face beside large ones at a sharp
//     crease of a CAD mesh): drawn as the dense mesh is, but shaded as the dense mesh's own
//     vertex normals shade that face, dark.
//   Not counted here: quads whose image overlaps another quad's without turning, and zero-area
//   triangles (their corners coincide: ChartStats::coincidentTexels counts those texels).
#pragma once
#include <cstdint>
#include <vector>

#include "atlas/atlas.h"

namespace isoatlas::atlas {

// Whether triangle (p0, p1, p2) faces against the surface whose normals at its corners are n0, n1, n2.
inline bool facesBackwards(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& n0, const Vec3& n1, const Vec3& n2) {
  return dot(cross(p1 - p0, p2 - p0), n0 + n1 + n2) < 0;
}

// Whether texel quad (a, b) of chart c (its corners (a, b) to (a + 1, b + 1)) turns against the
// atlas's normals, and against its dense faces' (throws Error(BadInput) without atlas.triangleFaceNormals).
bool quadFacesBackwards(const Atlas& atlas, std::uint32_t c, std::uint32_t a, std::uint32_t b);
bool quadFolds(const Atlas& atlas, std::uint32_t c, std::uint32_t a, std::uint32_t b);

struct BackFacingQuads {
  std::uint64_t quads = 0;        // texel quads turned so
  std::uint64_t total = 0;        // texel quads looked at (charts x (N - 1)^2)
  std::uint32_t charts = 0;       // charts with at least one
  std::uint32_t worstChart = 0;   // the chart with the most (0 when none)
  std::uint64_t worstChartQuads = 0;
  Vec3 worstChartCentre;          // where the worst chart lies: its centre texel, in world mm
  std::vector<std::uint64_t> perChart;  // by chart (tile), to say where
};

BackFacingQuads countBackFacingQuads(const Atlas& atlas);
// Throws Error(BadInput) for an atlas without triangleFaceNormals (one read from a model file).
BackFacingQuads countFoldedQuads(const Atlas& atlas);

}  // namespace isoatlas::atlas
