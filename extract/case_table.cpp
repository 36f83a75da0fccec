#include "extract/case_table.h"

#include <algorithm>
#include <array>

namespace isoatlas::extract {
namespace {

// The six faces, each as four corners counter-clockwise seen from outside the cell.
constexpr int kFaceCorners[6][4] = {
    {0, 4, 6, 2},  // x = 0, outward -x
    {1, 3, 7, 5},  // x = 1, outward +x
    {0, 1, 5, 4},  // y = 0, outward -y
    {2, 6, 7, 3},  // y = 1, outward +y
    {0, 2, 3, 1},  // z = 0, outward -z
    {4, 5, 7, 6},  // z = 1, outward +z
};

int edgeBetween(int a, int b) {
  for (int e = 0; e < 12; ++e)
    if ((kEdgeCorner[e][0] == a && kEdgeCorner[e][1] == b) || (kEdgeCorner[e][0] == b && kEdgeCorner[e][1] == a)) return e;
  return -1;
}

// For each of the 256 inside/outside patterns: the polygons, as cycles of cell edges, built from
// the per-face segments (entering crossing -> leaving crossing, walking each face counter-clockwise
// from outside; an ambiguous face cuts each inside corner off on its own).
bool onFace(int edge, int face) {
  int hits = 0;
  for (int k : kFaceCorners[face]) hits += (k == kEdgeCorner[edge][0]) + (k == kEdgeCorner[edge][1]);
  return hits == 2;
}
bool shareFace(int a, int b) {
  for (int f = 0; f < 6; ++f)
    if (onFace(a, f) && onFace(b, f)) return true;
  return false;
}

// A fan diagonal joining two crossings on one face could be drawn by the cell across that face too
// (an ambiguous face whose two segments both lie in one polygon on each side), giving an edge of four
// triangles. So the apex is chosen to draw no such diagonal; when none can, a centre vertex is used.
int chooseApex(const std::vector<std::int8_t>& cycle) {
  const int n = int(cycle.size());
  for (int a = 0; a < n; ++a) {
    bool ok = true;
    for (int i = 0; i < n && ok; ++i) {
      const bool adjacent = i == a || i == (a + 1) % n || (i + 1) % n == a;
      if (!adjacent && shareFace(cycle[std::size_t(a)], cycle[std::size_t(i)])) ok = false;
    }
    if (ok) return a;
  }
  return -1;
}

}  // namespace

CaseTable::CaseTable() {
  for (int c = 0; c < 256; ++c) {
    int next[12];
    std::fill(std::begin(next), std::end(next), -1);
    auto inside = [c](int corner) { return (c >> corner) & 1; };
    for (const auto& face : kFaceCorners) {
      for (int i = 0; i < 4; ++i) {
        const int corner = face[i];
        if (!inside(corner)) continue;
        const int before = face[(i + 3) % 4];
        if (inside(before)) continue;  // this inside run starts earlier on the face
        // Walk the inside run forward to its last corner; the run leaves on the following edge.
        int j = i;
        while (inside(face[(j + 1) % 4]) && (j + 1) % 4 != i) j = (j + 1) % 4;
        const int entering = edgeBetween(before, corner);
        const int leaving = edgeBetween(face[j], face[(j + 1) % 4]);
        next[entering] = leaving;
      }
    }
    bool used[12] = {};
    for (int e = 0; e < 12; ++e) {
      if (next[e] < 0 || used[e]) continue;
      std::vector<std::int8_t> cycle;
      for (int k = e; !used[k]; k = next[k]) {
        used[k] = true;
        cycle.push_back(std::int8_t(k));
      }
      const int apex = chooseApex(cycle);
      polygons[std::size_t(c)].push_back({cycle, apex});
    }
  }
}

const CaseTable& caseTable() {
  static const CaseTable table;
  return table;
}

const PackedCaseTable& packedCaseTable() {
  static const PackedCaseTable packed = [] {
    PackedCaseTable p;
    for (const auto& polygons : caseTable().polygons) {
      p.index.push_back(std::int32_t(p.polygons.size()));
      p.index.push_back(std::int32_t(polygons.size()));
      for (const Polygon& polygon : polygons) {
        p.polygons.push_back(polygon.apex);
        p.polygons.push_back(std::int32_t(polygon.edges.size()));
        for (std::int8_t e : polygon.edges) p.polygons.push_back(e);
      }
    }
    return p;
  }();
  return packed;
}

}  // namespace isoatlas::extract
