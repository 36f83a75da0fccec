#include "multires/mapped_points.h"

namespace isoatlas::multires::simplify {

void ringPoints(const StellarMesh& mesh, const FacePoints& facePoints, VertexH v, const OneRing& ring,
                const std::vector<Vec2>& plane, std::vector<FanPoint>& points, std::vector<MappedPoint>* region) {
  const Vec3 pv = pointOf(mesh, v);
  points.assign(1, {pv, {0, 0}});
  if (region) region->assign(1, {std::uint32_t(v.idx()), {v.idx(), v.idx(), v.idx()}, {1, 0, 0}, pv});
  const std::size_t k = ring.vertices.size();
  // The faces' lists lie far apart in memory: their first lines are fetched all at once.
  for (const FaceH f : ring.faces) __builtin_prefetch(&facePoints[f.idx()]);
  for (const FaceH f : ring.faces)
    if (!facePoints[f.idx()].empty()) __builtin_prefetch(facePoints[f.idx()].data());
  for (std::size_t i = 0; i < ring.faces.size(); ++i) {
    // A point of ring face i is weighted on that face's corners: v, ring vertex i and i + 1.
    auto planeOf = [&](int vertex) {
      return vertex == v.idx() ? Vec2{0, 0} : vertex == ring.vertices[i].idx() ? plane[i] : plane[(i + 1) % k];
    };
    for (const MappedPoint& m : facePoints[ring.faces[i].idx()]) {
      points.push_back({m.position, planeOf(m.vertices[0]) * m.bary[0] + planeOf(m.vertices[1]) * m.bary[1] +
                                        planeOf(m.vertices[2]) * m.bary[2]});
      if (region) region->push_back(m);
    }
  }
}

}  // namespace isoatlas::multires::simplify
