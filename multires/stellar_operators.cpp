#include "multires/stellar_operators.h"

#include "core/error.h"

namespace isoatlas::multires {

OneRing oneRing(const StellarMesh& mesh, VertexH v) {
  OneRing ring;
  oneRing(mesh, v, ring);
  return ring;
}

void oneRing(const StellarMesh& mesh, VertexH v, OneRing& ring) {
  ring.vertices.clear();
  ring.faces.clear();
  ring.boundary = false;
  HalfedgeH start = mesh.halfedge_handle(v);
  if (!start.is_valid()) return;
  // OpenMesh keeps a boundary vertex's outgoing halfedge on the boundary: start just after it.
  ring.boundary = mesh.is_boundary(start);
  if (ring.boundary) start = mesh.opposite_halfedge_handle(mesh.prev_halfedge_handle(start));
  HalfedgeH h = start;
  do {
    ring.vertices.push_back(mesh.to_vertex_handle(h));
    const FaceH f = mesh.face_handle(h);
    if (!f.is_valid()) break;
    ring.faces.push_back(f);
    h = mesh.opposite_halfedge_handle(mesh.prev_halfedge_handle(h));
  } while (h != start);
}

namespace {
// OpenMesh's valence() through a circulator costs more than this walk around the vertex.
unsigned degree(const StellarMesh& mesh, VertexH v) {
  const HalfedgeH start = mesh.halfedge_handle(v);
  unsigned n = 0;
  HalfedgeH h = start;
  do {
    ++n;
    h = mesh.next_halfedge_handle(mesh.opposite_halfedge_handle(h));
  } while (h != start);
  return n;
}
}  // namespace

DegreeTable degreeTable(const StellarMesh& mesh) {
  DegreeTable degrees(mesh.n_vertices(), 0);
  for (const VertexH v : mesh.vertices())
    if (mesh.halfedge_handle(v).is_valid()) degrees[v.idx()] = degree(mesh, v);
  return degrees;
}

bool canWeldInto(const StellarMesh& mesh, VertexH v, VertexH u, const DegreeTable* degrees) {
  auto degreeOf = [&](VertexH w) { return degrees ? (*degrees)[w.idx()] : degree(mesh, w); };
  const HalfedgeH h = mesh.find_halfedge(v, u);
  if (!h.is_valid()) return false;
  const bool boundary = mesh.is_boundary(v);
  if (boundary) {
    // Along the boundary only, and never closing a loop of three boundary edges.
    if (!mesh.is_boundary(mesh.edge_handle(h))) return false;
    const HalfedgeH hb = mesh.is_boundary(h) ? h : mesh.opposite_halfedge_handle(h);
    if (mesh.next_halfedge_handle(mesh.next_halfedge_handle(mesh.next_halfedge_handle(hb))) == hb) return false;
  } else if (mesh.is_boundary(u) && degreeOf(u) <= 2) {
    return false;
  }
  // The opposite vertices (one or two) lose a neighbour: keep every vertex at degree >= 3 (2 on a
  // boundary), and remember them for the link condition.
  VertexH opposite[2];
  int opposites = 0;
  for (const HalfedgeH side : {h, mesh.opposite_halfedge_handle(h)}) {
    if (mesh.is_boundary(side)) continue;
    const VertexH o = mesh.to_vertex_handle(mesh.next_halfedge_handle(side));
    if (degreeOf(o) <= (mesh.is_boundary(o) ? 2u : 3u)) return false;
    opposite[opposites++] = o;
  }
  if (opposites == 2 && opposite[0] == opposite[1]) return false;
  // Link condition: v and u have no common neighbour but the opposite vertices (else the weld
  // would pinch the surface and change its topology).
  int neighbours[kMaxDegree], count = 0;
  const HalfedgeH first = mesh.halfedge_handle(v);
  HalfedgeH g = first;
  do {
    if (count == int(kMaxDegree)) return false;
    neighbours[count++] = mesh.to_vertex_handle(g).idx();
    g = mesh.next_halfedge_handle(mesh.opposite_halfedge_handle(g));
  } while (g != first);
  int common = 0;
  const HalfedgeH firstU = mesh.halfedge_handle(u);
  g = firstU;
  do {
    const int y = mesh.to_vertex_handle(g).idx();
    for (int i = 0; i < count; ++i)
      if (neighbours[i] == y) {
        if (y != opposite[0].idx() && (opposites < 2 || y != opposite[1].idx())) return false;
        ++common;
      }
    g = mesh.next_halfedge_handle(mesh.opposite_halfedge_handle(g));
  } while (g != firstU);
  return common == opposites;
}

WeldCounts weldInto(StellarMesh& mesh, VertexH v, VertexH u, DegreeTable* degrees, std::span<const VertexH> spokes) {
  WeldCounts counts;
  const bool boundary = mesh.is_boundary(v);
  auto flip = [&](HalfedgeH g) {
    if (!g.is_valid() || !mesh.is_flip_ok(mesh.edge_handle(g))) throw Error("stellar weld: a flip in a checked 1-ring failed", ErrorKind::Failure);
    mesh.flip(mesh.edge_handle(g));
    ++counts.flips;
  };
  for (const VertexH w : spokes) flip(mesh.find_halfedge(v, w));
  // An interior vertex goes down to degree 4 (then an edge weld, or a face weld if it had 3); a
  // boundary vertex down to two faces (three neighbours).
  const unsigned target = boundary ? 3 : 4;
  while (degree(mesh, v) > target) {
    const HalfedgeH h = mesh.find_halfedge(v, u);
    const HalfedgeH back = mesh.opposite_halfedge_handle(h);
    // Flip the edge from v to u's neighbour in the ring: the quad's new diagonal ends at u.
    flip(mesh.is_boundary(back) ? mesh.opposite_halfedge_handle(mesh.prev_halfedge_handle(h)) : mesh.next_halfedge_handle(back));
  }
  if (boundary) ++counts.boundaryWelds;
  else if (degree(mesh, v) == 3) ++counts.faceWelds;
  else ++counts.edgeWelds;
  mesh.collapse(mesh.find_halfedge(v, u));
  if (degrees) {
    (*degrees)[v.idx()] = 0;
    (*degrees)[u.idx()] = degree(mesh, u);
    for (const VertexH w : mesh.vv_range(u)) (*degrees)[w.idx()] = degree(mesh, w);
  }
  return counts;
}

VertexH splitEdge(StellarMesh& mesh, EdgeH e, const Vec3& position) {
  const VertexH m = mesh.add_vertex(toPoint(position));
  mesh.split(e, m);
  return m;
}

}  // namespace isoatlas::multires
