#include "multires/weld_fan_checks.h"

#include "multires/exact_orientation.h"

namespace isoatlas::multires::simplify {

DenseStars::DenseStars(const Mesh& dense) {
  const Rows faces = vertexFaces(dense.vertexCount(), dense.faceCount(), [&](std::size_t f) { return dense.face(f); });
  offsets = faces.offsets;
  opposite.resize(faces.items.size());
  for (std::size_t a = 0; a + 1 < offsets.size(); ++a)
    for (std::uint32_t j = offsets[a]; j < offsets[a + 1]; ++j) {
      const auto c = dense.face(faces.items[j]);
      const std::size_t at = c[0] == a ? 0 : c[1] == a ? 1 : 2;
      opposite[j] = {c[(at + 1) % 3], c[(at + 2) % 3]};
    }
}

bool locateInFan(VertexH v, const OneRing& ring, const std::vector<Vec2>& plane, const WeldPlan& plan,
                 const std::vector<FanPoint>& points, const std::vector<MappedPoint>& region,
                 std::vector<TriangleHit>& hits) {
  const std::size_t t = plan.target;
  const VertexH u = ring.vertices[t];
  const std::size_t fanFaces = plan.rimSize - 1;
  auto fanFace = [&](std::size_t m) { return std::array<Vec2, 3>{plane[t], plane[plan.rim[m]], plane[plan.rim[m + 1]]}; };
  hits.resize(points.size());
  std::size_t hint = 0;
  bool located = true;
  auto onBorder = [&](std::size_t i, TriangleHit& hit) {
    if (i == 0) return false;
    const MappedPoint& m = region[i];
    int at = -1;
    for (int c = 0; c < 3; ++c)
      if (m.vertices[c] == v.idx()) at = c;
    if (at < 0 || m.bary[at] != 0) return false;
    for (std::size_t f = 0; f < fanFaces; ++f) {
      const int corners[3] = {u.idx(), ring.vertices[plan.rim[f]].idx(), ring.vertices[plan.rim[f + 1]].idx()};
      std::array<double, 3> bary{};
      int found = 0;
      for (int c = 0; c < 3; ++c)
        for (const int e : {(at + 1) % 3, (at + 2) % 3})
          if (corners[c] == m.vertices[e]) bary[c] = m.bary[e], ++found;
      if (found == 2) {
        hit = {f, bary, true};
        return true;
      }
    }
    return false;
  };
  for (std::size_t i = 0; i < points.size() && located; ++i) {
    if (onBorder(i, hits[i])) continue;
    hits[i] = locateExactly(points[i].plane, fanFaces, fanFace, hint);
    located = hits[i].triangle != kNoTriangleHit;
    hint = located ? hits[i].triangle : 0;
  }
  return located;
}

bool denseTrianglesTurnLeft(const DenseStars& denseStars, std::size_t vertexCount, const std::vector<FanPoint>& points,
                            const std::vector<MappedPoint>& region, const OneRing& ring, const std::vector<Vec2>& plane,
                            std::vector<std::int32_t>& regionIndex, std::vector<Vec2>& regionPlane) {
  if (regionIndex.empty()) regionIndex.assign(vertexCount, -1);
  std::vector<Vec2>& at = regionPlane;
  at.clear();
  auto mark = [&](std::uint32_t vertex, const Vec2& p) {
    regionIndex[vertex] = std::int32_t(at.size());
    at.push_back(p);
  };
  // The points' dense vertices lie far apart in the tables: each one's entries are fetched a few
  // points ahead, and its star as it is marked, ahead of the test below.
  constexpr std::size_t kAhead = 8;
  for (std::size_t i = 0; i < region.size(); ++i) {
    if (i + kAhead < region.size()) {
      __builtin_prefetch(&regionIndex[region[i + kAhead].id], 1);
      __builtin_prefetch(&denseStars.offsets[region[i + kAhead].id]);
    }
    __builtin_prefetch(denseStars.of(region[i].id).data());
    mark(region[i].id, points[i].plane);
  }
  for (std::size_t i = 0; i < ring.vertices.size(); ++i) mark(std::uint32_t(ring.vertices[i].idx()), plane[i]);
  bool ok = true;
  for (std::size_t i = 0; i < region.size() && ok; ++i)
    for (const auto& [second, third] : denseStars.of(region[i].id)) {
      const std::int32_t b = regionIndex[second], d = regionIndex[third];
      // Once per face inside: from its corner that comes first among the inner points.
      if (b <= std::int32_t(i) || d <= std::int32_t(i)) continue;
      if (exactOrientation(at[i], at[std::size_t(b)], at[std::size_t(d)]) <= 0) {
        ok = false;
        break;
      }
    }
  for (const MappedPoint& m : region) regionIndex[m.id] = -1;
  for (const VertexH w : ring.vertices) regionIndex[w.idx()] = -1;
  return ok;
}

}  // namespace isoatlas::multires::simplify
