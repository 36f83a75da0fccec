// Which side of a closed triangle mesh a point is on, from its closest point on the mesh: the sign
// of the offset to it along the angle-weighted pseudonormal of the feature (face, edge or vertex)
// the closest point lies on (Baerentzen and Aanaes, "Signed distance computation using the angle
// weighted pseudonormal", 2005). Exact for a closed, consistently oriented, non-self-intersecting
// mesh; one closest-point query per point, where a ray's crossings need a second, longer one.
//   closestOnTriangle: the closest point of a triangle to p and the feature it lies on.
//   PseudoNormals: per face its unit normal, per vertex its angle-weighted pseudonormal, per edge the
//   two faces' sum, each component turned outward (`insideAt` decides probes off 7 of its faces,
//   so a cavity, or a component stored inside out, is told from a shell; where they disagree, as
//   where closed shells overlap, the normals are not usable).
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "core/mesh.h"

namespace isoatlas::edit::dvt {

// Features of a triangle (a, b, c): its corners 0-2, its edges 3-5 (edge 3 + i runs from corner i to
// corner i + 1), its inside 6.
inline constexpr int kEdgeFeature = 3, kFaceFeature = 6;
struct ClosestOnTriangle {
  Vec3 point;
  int feature = kFaceFeature;
};
ClosestOnTriangle closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

class PseudoNormals {
public:
  // `mesh`: closed triangles, each component consistently oriented (analyzeTopology's `oriented`).
  // insideAt(q): whether q is inside the solid, asked twice for each of up to 7 faces per component.
  PseudoNormals(const Mesh& mesh, const std::function<bool(const Vec3&)>& insideAt);
  // False when some component's outward side could not be told (a probe's two sides agreed, or two
  // probes of one component disagreed).
  bool usable() const { return usable_; }
  // p's signed distance (< 0 inside) to the mesh when `face` is a closest triangle to p; nullopt where
  // the pseudonormal cannot tell (a degenerate feature, or p too near its tangent plane to trust).
  std::optional<double> signedDistance(const Vec3& p, std::size_t face) const;

private:
  std::vector<Vec3> positions_;
  std::vector<std::array<std::uint32_t, 3>> faces_;
  std::vector<Vec3> faceNormals_;                      // unit, outward; zero for a degenerate face
  std::vector<std::array<std::uint32_t, 3>> across_;   // the face across each edge
  std::vector<Vec3> vertexNormals_;                    // angle-weighted sums of outward face normals
  bool usable_ = true;
};

}  // namespace isoatlas::edit::dvt
