#include "multires/adaptive_mesh.h"

#include <algorithm>
#include <map>

#include "core/error.h"
#include "multires/stellar_operators.h"

namespace isoatlas::multires {
namespace {

using UvTable = std::vector<std::pair<int, std::array<int, 2>>>;  // vertex -> texel uv on one chart

const std::array<int, 2>& lookup(const UvTable& table, int vertex) {
  for (const auto& [v, uv] : table)
    if (v == vertex) return uv;
  throw Error("adaptive mesh: a vertex has no (u, v) on its chart", ErrorKind::Failure);
}

}  // namespace

// The storage the class documents is the storage its properties take.
static_assert(sizeof(std::uint32_t) + sizeof(std::array<std::uint8_t, 4>) == AdaptiveMesh::kBytesPerHalfedge);
static_assert(sizeof(std::uint8_t) == AdaptiveMesh::kBytesPerVertex);
static_assert(sizeof(HalfedgeH) == AdaptiveMesh::kBytesPerFace);

AdaptiveMesh::AdaptiveMesh(const BaseMesh& base, std::uint32_t chartSize, Sampler sampler)
    : chartSize_(chartSize), charts_(std::uint32_t(base.tiles.size())), sampler_(std::move(sampler)) {
  require(isChartSize(chartSize), "adaptive mesh: the chart size must be 2^k + 1 between 3 and " +
                                      std::to_string(kMaxChartSize));
  require(!base.tiles.empty() && base.tiles.size() * 2 == base.triangleCount(),
          "adaptive mesh: the base mesh must be paired into tiles first");
  mesh_ = toStellarMesh(base.triangleMesh(), "adaptive mesh");  // the base's vertex and face indices
  mesh_.add_property(chart_);
  mesh_.add_property(uv_);
  mesh_.add_property(interior_);
  mesh_.add_property(level_);
  for (const VertexH v : mesh_.vertices()) mesh_.property(level_, v) = 0;
  const int n = int(chartSize - 1);
  for (std::uint32_t i = 0; i < base.tiles.size(); ++i) {
    const BaseMesh::TileCorners c = base.tileCorners(i);
    const UvTable table{{int(c.p), {0, 0}}, {int(c.s), {n, 0}}, {int(c.q), {n, n}}, {int(c.r), {0, n}}};
    setFace(FaceH(int(base.tiles[i][0])), i, table);
    setFace(FaceH(int(base.tiles[i][1])), i, table);
  }
}

// Sets the chart and (u, v) of f's halfedges from `uvOf`, and f's interior halfedge: the one across
// from the corner of highest level (the newest vertex), or at the base the tile's diagonal, which is
// the edge whose (u, v) runs corner to corner.
void AdaptiveMesh::setFace(FaceH f, std::uint32_t chart, const UvTable& uvOf) {
  HalfedgeH interior;
  int newest = -1;
  for (const HalfedgeH h : mesh_.fh_range(f)) {
    const auto& s = lookup(uvOf, mesh_.from_vertex_handle(h).idx());
    const auto& e = lookup(uvOf, mesh_.to_vertex_handle(h).idx());
    mesh_.property(chart_, h) = chart;
    mesh_.property(uv_, h) = {std::uint8_t(s[0]), std::uint8_t(s[1]), std::uint8_t(e[0]), std::uint8_t(e[1])};
    const VertexH apex = mesh_.to_vertex_handle(mesh_.next_halfedge_handle(h));
    const int l = level(apex);
    const bool diagonal = s[0] != e[0] && s[1] != e[1];  // base faces: the only edge not along a side
    if (l > newest || (l == newest && newest == 0 && diagonal)) newest = l, interior = h;
  }
  mesh_.property(interior_, f) = interior;
}

void AdaptiveMesh::compact() {
  // Face properties move with their faces, but a stored halfedge handle is not renumbered: keep
  // each interior halfedge as its place in the face's cycle across the collection.
  OpenMesh::FPropHandleT<std::uint8_t> place;
  mesh_.add_property(place);
  for (const FaceH f : mesh_.faces()) {
    std::uint8_t k = 0;
    for (HalfedgeH h = mesh_.halfedge_handle(f); h != mesh_.property(interior_, f); h = mesh_.next_halfedge_handle(h)) ++k;
    mesh_.property(place, f) = k;
  }
  mesh_.garbage_collection();
  for (const FaceH f : mesh_.faces()) {
    HalfedgeH h = mesh_.halfedge_handle(f);
    for (int k = 0; k < mesh_.property(place, f); ++k) h = mesh_.next_halfedge_handle(h);
    mesh_.property(interior_, f) = h;
  }
  mesh_.remove_property(place);
}

int AdaptiveMesh::level(VertexH v) const { return mesh_.property(level_, v) & 0x7f; }
bool AdaptiveMesh::isInterior(HalfedgeH h) const {
  const FaceH f = mesh_.face_handle(h);
  return f.is_valid() && mesh_.property(interior_, f) == h;
}
std::uint32_t AdaptiveMesh::chart(HalfedgeH h) const { return mesh_.property(chart_, h); }
std::array<int, 4> AdaptiveMesh::uv(HalfedgeH h) const {
  const auto& x = mesh_.property(uv_, h);
  return {x[0], x[1], x[2], x[3]};
}

int AdaptiveMesh::faceLevel(FaceH f) const {
  int l = 0;
  for (const VertexH v : mesh_.fv_range(f)) l = std::max(l, level(v));
  return l;
}

bool AdaptiveMesh::canSplit(EdgeH e) const {
  bool any = false;
  for (int i = 0; i < 2; ++i) {
    const HalfedgeH h = mesh_.halfedge_handle(e, i);
    if (mesh_.is_boundary(h)) continue;
    if (!isInterior(h)) return false;
    const auto x = uv(h);
    if ((x[0] + x[2]) % 2 != 0 || (x[1] + x[3]) % 2 != 0) return false;  // finer than the chart
    any = true;
  }
  return any;
}

VertexH AdaptiveMesh::split(EdgeH e) {
  if (!canSplit(e)) throw Error("adaptive mesh: split of an edge that is not splittable", ErrorKind::Failure);
  struct Side {
    std::uint32_t chart;
    UvTable table;
    std::array<int, 2> mid;
    int apex;
  };
  std::vector<Side> sides;
  int newLevel = 0;
  bool diagonalPlus = false;
  for (int i = 0; i < 2; ++i) {
    const HalfedgeH h = mesh_.halfedge_handle(e, i);
    if (mesh_.is_boundary(h)) continue;
    const auto x = uv(h);
    Side side{chart(h), {}, {(x[0] + x[2]) / 2, (x[1] + x[3]) / 2},
              mesh_.to_vertex_handle(mesh_.next_halfedge_handle(h)).idx()};
    for (const HalfedgeH g : mesh_.fh_range(mesh_.face_handle(h))) {
      const auto y = uv(g);
      side.table.push_back({mesh_.from_vertex_handle(g).idx(), {y[0], y[1]}});
    }
    newLevel = std::max(newLevel, faceLevel(mesh_.face_handle(h)) + 1);
    diagonalPlus = (x[2] - x[0]) * (x[3] - x[1]) > 0;
    sides.push_back(std::move(side));
  }
  const VertexH m = splitEdge(mesh_, e, *splitPosition(e));
  mesh_.property(level_, m) = std::uint8_t(newLevel | ((newLevel % 2 == 1 && diagonalPlus) ? 0x80 : 0));
  for (Side& side : sides) side.table.push_back({m.idx(), side.mid});
  for (const FaceH f : mesh_.vf_range(m))
    for (const Side& side : sides) {
      bool hasApex = false;
      for (const VertexH w : mesh_.fv_range(f)) hasApex |= w.idx() == side.apex;
      if (hasApex) setFace(f, side.chart, side.table);
    }
  return m;
}

std::optional<Vec3> AdaptiveMesh::splitPosition(EdgeH e) const {
  // On a tile side, the chart of lower index is sampled, so the new vertex does not depend on which
  // side the edge's handle happens to start from (the two charts' samples agree only within
  // rounding).
  HalfedgeH from;
  for (int i = 0; i < 2; ++i) {
    const HalfedgeH h = mesh_.halfedge_handle(e, i);
    if (!mesh_.is_boundary(h) && (!from.is_valid() || chart(h) < chart(from))) from = h;
  }
  const auto x = uv(from);
  if ((x[0] + x[2]) % 2 != 0 || (x[1] + x[3]) % 2 != 0) return std::nullopt;
  const double n = chartSize_ - 1;
  return sampler_({chart(from), (x[0] + x[2]) / 2 / n, (x[1] + x[3]) / 2 / n});
}

bool AdaptiveMesh::canWeld(VertexH v) const {
  if (level(v) == 0 || mesh_.status(v).deleted()) return false;
  const bool boundary = mesh_.is_boundary(v);
  if (mesh_.valence(v) != (boundary ? 3u : 4u)) return false;
  for (const HalfedgeH h : mesh_.voh_range(v))
    if (isInterior(h) || isInterior(mesh_.opposite_halfedge_handle(h))) return false;
  return true;
}

std::array<VertexH, 2> AdaptiveMesh::weldParents(VertexH v) const {
  if (!canWeld(v)) throw Error("adaptive mesh: weld of a vertex that is not weldable", ErrorKind::Failure);
  const int l = level(v);
  // The edge the split cut: at an even level, between the two neighbours two levels up; at an odd
  // level (a square's centre), the diagonal the level byte names.
  std::vector<VertexH> ends;
  for (const HalfedgeH h : mesh_.voh_range(v)) {
    const VertexH w = mesh_.to_vertex_handle(h);
    bool parent;
    if (l % 2 == 0) {
      parent = level(w) <= l - 2;
    } else {
      if (mesh_.is_boundary(h)) continue;
      const auto x = uv(h);
      parent = ((x[2] - x[0]) * (x[3] - x[1]) > 0) == bool(mesh_.property(level_, v) & 0x80);
    }
    if (parent) ends.push_back(w);
  }
  if (ends.size() != 2 || !canWeldInto(mesh_, v, ends[0]))
    throw Error("adaptive mesh: the edge a vertex was split from cannot be found", ErrorKind::Failure);
  return {ends[0], ends[1]};
}

void AdaptiveMesh::weld(VertexH v) {
  const VertexH into = weldParents(v)[0];
  // OpenMesh's collapse merges edges of the faces around v's neighbours too, moving halfedges
  // (and their properties) between faces: note every face within two rings, and set them again.
  std::map<std::uint32_t, UvTable> tables;  // per chart
  std::vector<std::pair<FaceH, std::uint32_t>> faces;
  std::vector<VertexH> around{v};
  for (const VertexH w : mesh_.vv_range(v)) around.push_back(w);
  for (const VertexH w : around)
    for (const FaceH f : mesh_.vf_range(w)) {
      if (std::any_of(faces.begin(), faces.end(), [&](const auto& x) { return x.first == f; })) continue;
      const HalfedgeH first = *mesh_.fh_range(f).begin();
      faces.push_back({f, chart(first)});
      for (const HalfedgeH g : mesh_.fh_range(f)) {
        const auto y = uv(g);
        tables[chart(g)].push_back({mesh_.from_vertex_handle(g).idx(), {y[0], y[1]}});
      }
    }
  weldInto(mesh_, v, into);
  for (const auto& [f, c] : faces)
    if (!mesh_.status(f).deleted()) setFace(f, c, tables[c]);
}

bool AdaptiveMesh::refine(EdgeH e) {
  for (int guard = 0; guard < 256; ++guard) {
    if (canSplit(e)) {
      split(e);
      return true;
    }
    bool forced = false;
    for (int i = 0; i < 2 && !forced; ++i) {
      const HalfedgeH h = mesh_.halfedge_handle(e, i);
      if (mesh_.is_boundary(h) || isInterior(h)) continue;
      // The neighbour must first split its own interior edge; then e borders its child.
      if (!refine(mesh_.edge_handle(mesh_.property(interior_, mesh_.face_handle(h))))) return false;
      forced = true;
    }
    if (!forced) return false;  // both sides interior, but finer than the chart
  }
  return false;
}

std::vector<Patch> AdaptiveMesh::patches() const {
  const int n = int(chartSize_ - 1);
  // Odd-level vertices strictly inside each chart, with their (u, v).
  std::map<std::uint32_t, std::vector<std::array<int, 3>>> inside;
  std::vector<char> seen(mesh_.n_vertices(), 0);
  for (const HalfedgeH h : mesh_.halfedges()) {
    if (mesh_.is_boundary(h)) continue;
    const VertexH v = mesh_.from_vertex_handle(h);
    const auto x = uv(h);
    if (seen[v.idx()] || level(v) % 2 == 0 || x[0] <= 0 || x[0] >= n || x[1] <= 0 || x[1] >= n) continue;
    seen[v.idx()] = 1;
    inside[chart(h)].push_back({x[0], x[1], level(v)});
  }
  std::vector<Patch> out;
  std::function<void(std::uint32_t, int, int, int)> visit = [&](std::uint32_t c, int u, int v, int s) {
    int count = 0, finest = 0;
    for (const auto& p : inside[c])
      if (p[0] > u && p[0] < u + s && p[1] > v && p[1] < v + s) ++count, finest = std::max(finest, p[2]);
    if (count > 1 && s >= 4) {
      const int h = s / 2;
      visit(c, u, v, h), visit(c, u + h, v, h), visit(c, u, v + h, h), visit(c, u + h, v + h, h);
      return;
    }
    out.push_back({c, std::uint16_t(u), std::uint16_t(v), std::uint16_t(s), std::uint8_t(finest)});
  };
  for (std::uint32_t c = 0; c < charts_; ++c) visit(c, 0, 0, n);
  return out;
}

}  // namespace isoatlas::multires
