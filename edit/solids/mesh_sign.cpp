#include "edit/solids/mesh_sign.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/union_find.h"

namespace isoatlas::edit::dvt {

// By the Voronoi regions of the triangle's features, tested in turn from the corners (Ericson,
// Real-Time Collision Detection, 5.1.5).
ClosestOnTriangle closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return {a, 0};
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return {b, 1};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return {a + ab * (d1 / (d1 - d3)), kEdgeFeature + 0};
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return {c, 2};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return {a + ac * (d2 / (d2 - d6)), kEdgeFeature + 2};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return {b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))), kEdgeFeature + 1};
  const double denom = 1 / (va + vb + vc);
  return {a + ab * (vb * denom) + ac * (vc * denom), kFaceFeature};
}

namespace {

double angleBetween(const Vec3& u, const Vec3& v) {
  const double lu = norm(u), lv = norm(v);
  if (lu == 0 || lv == 0) return 0;
  return std::acos(std::clamp(dot(u, v) / (lu * lv), -1.0, 1.0));
}

}  // namespace

PseudoNormals::PseudoNormals(const Mesh& mesh, const std::function<bool(const Vec3&)>& insideAt) : positions_(mesh.positions) {
  require(mesh.allFacesHave(3), "pseudonormals need a triangle mesh");
  const std::size_t F = mesh.faceCount();
  faces_.resize(F);
  faceNormals_.resize(F);
  UnionFind components(mesh.vertexCount());
  for (std::size_t f = 0; f < F; ++f) {
    const auto c = mesh.face(f);
    faces_[f] = {c[0], c[1], c[2]};
    const Vec3 n = cross(positions_[c[1]] - positions_[c[0]], positions_[c[2]] - positions_[c[0]]);
    const double length = norm(n);
    faceNormals_[f] = length > 0 ? n * (1 / length) : Vec3{0, 0, 0};
    components.unite(c[0], c[1]), components.unite(c[0], c[2]);
  }

  across_ = triangleNeighbours(faces_);
  for (const auto& across : across_)
    require(std::find(across.begin(), across.end(), kNoTriangle) == across.end(), "pseudonormals need a closed, consistently oriented mesh");

  // Each component's outward side: a probe a little off each side of its largest face and of its
  // faces farthest along each axis, both ways (spread over it). They must all agree: a face inside
  // another component (closed shells that overlap) reads inside out, and then the whole mesh is left
  // to the caller's parity.
  auto centreOf = [&](std::size_t f) { return (positions_[faces_[f][0]] + positions_[faces_[f][1]] + positions_[faces_[f][2]]) * (1.0 / 3); };
  auto sizeOf = [&](std::size_t f) {
    return std::sqrt(norm(cross(positions_[faces_[f][1]] - positions_[faces_[f][0]], positions_[faces_[f][2]] - positions_[faces_[f][0]])));
  };
  constexpr int kProbes = 7;  // the largest face, then the least and the most along x, y and z
  std::vector<std::array<std::int64_t, kProbes>> probes(mesh.vertexCount());
  for (auto& p : probes) p.fill(-1);
  for (std::size_t f = 0; f < F; ++f) {
    if (norm(faceNormals_[f]) == 0) continue;
    auto& p = probes[components.find(faces_[f][0])];
    if (p[0] < 0 || sizeOf(f) > sizeOf(std::size_t(p[0]))) p[0] = std::int64_t(f);
    for (int axis = 0; axis < 3; ++axis) {
      if (p[1 + 2 * axis] < 0 || centreOf(f)[axis] < centreOf(std::size_t(p[1 + 2 * axis]))[axis]) p[1 + 2 * axis] = std::int64_t(f);
      if (p[2 + 2 * axis] < 0 || centreOf(f)[axis] > centreOf(std::size_t(p[2 + 2 * axis]))[axis]) p[2 + 2 * axis] = std::int64_t(f);
    }
  }
  std::vector<double> outward(mesh.vertexCount(), 0);  // per component root: +1 as stored, -1 inside out
  for (std::size_t f = 0; f < F && usable_; ++f) {
    const std::uint32_t root = components.find(faces_[f][0]);
    if (outward[root] != 0) continue;
    if (probes[root][0] < 0) usable_ = false;  // every face of it degenerate
    for (const std::int64_t g : probes[root]) {
      if (g < 0 || !usable_) break;
      const Vec3 offset = faceNormals_[std::size_t(g)] * (1e-3 * sizeOf(std::size_t(g)));
      const bool front = insideAt(centreOf(std::size_t(g)) + offset), back = insideAt(centreOf(std::size_t(g)) - offset);
      const double verdict = front ? -1 : 1;
      if (front == back || (outward[root] != 0 && outward[root] != verdict)) usable_ = false;
      outward[root] = verdict;
    }
  }
  for (std::size_t f = 0; f < F; ++f) faceNormals_[f] = faceNormals_[f] * outward[components.find(faces_[f][0])];

  vertexNormals_.assign(mesh.vertexCount(), Vec3{0, 0, 0});
  for (std::size_t f = 0; f < F; ++f)
    for (int i = 0; i < 3; ++i) {
      const Vec3& at = positions_[faces_[f][i]];
      const double angle = angleBetween(positions_[faces_[f][(i + 1) % 3]] - at, positions_[faces_[f][(i + 2) % 3]] - at);
      vertexNormals_[faces_[f][i]] = vertexNormals_[faces_[f][i]] + faceNormals_[f] * angle;
    }
}

std::optional<double> PseudoNormals::signedDistance(const Vec3& p, std::size_t face) const {
  const auto& v = faces_[face];
  const ClosestOnTriangle closest = closestOnTriangle(p, positions_[v[0]], positions_[v[1]], positions_[v[2]]);
  const Vec3 offset = p - closest.point;
  const double distance = norm(offset);
  if (distance == 0) return 0.0;
  Vec3 normal;
  if (closest.feature == kFaceFeature) normal = faceNormals_[face];
  else if (closest.feature >= kEdgeFeature) {
    const Vec3& other = faceNormals_[across_[face][closest.feature - kEdgeFeature]];
    if (norm(faceNormals_[face]) == 0 || norm(other) == 0) return std::nullopt;  // a degenerate face: no pseudonormal
    normal = faceNormals_[face] + other;
  }
  else normal = vertexNormals_[v[closest.feature]];
  const double side = dot(offset, normal);
  // Near the tangent plane, rounding could pick the side: let the caller ask otherwise (also NaN).
  if (!(std::abs(side) > 1e-9 * distance * norm(normal))) return std::nullopt;
  return side > 0 ? distance : -distance;
}

}  // namespace isoatlas::edit::dvt
