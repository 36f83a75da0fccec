#include "multires/triangle_pairing.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <queue>

#include "core/error.h"
#include "multires/max_weight_matching.h"

namespace isoatlas::multires {
namespace {

constexpr std::uint32_t kNone = BaseMesh::kNoTriangle;

double cornerCos(const Vec3& at, const Vec3& a, const Vec3& b) {
  const Vec3 u = a - at, v = b - at;
  const double l = norm(u) * norm(v);
  return l > 0 ? std::abs(dot(u, v)) / l : 1;
}

// 1 - mean |cos| of the corners of the quad (p, s, q, r) made by the triangles (p, q, r) and (q, p, s).
double orthogonality(const Vec3& p, const Vec3& s, const Vec3& q, const Vec3& r) {
  return 1 - (cornerCos(p, s, r) + cornerCos(s, q, p) + cornerCos(q, r, s) + cornerCos(r, p, q)) / 4;
}

using Neighbours = std::vector<std::array<std::uint32_t, 3>>;

// Per base vertex: the fewest tiles it may lie in (3 inside, 2 on the boundary: fewer make a tile
// corner of about 180 degrees, where a tile's two triangles would fold over its neighbour's), and
// how many triangles lie around it.
struct VertexRoom {
  std::vector<std::uint8_t> fewestTiles;
  std::vector<std::uint32_t> triangles;
};
VertexRoom vertexRoom(const BaseMesh& base, const Neighbours& across) {
  VertexRoom room{std::vector<std::uint8_t>(base.vertexCount(), 3), std::vector<std::uint32_t>(base.vertexCount(), 0)};
  for (std::uint32_t t = 0; t < base.triangleCount(); ++t)
    for (int i = 0; i < 3; ++i) {
      ++room.triangles[base.triangles[t][i]];
      if (across[t][i] == kNone) room.fewestTiles[base.triangles[t][i]] = room.fewestTiles[base.triangles[t][(i + 1) % 3]] = 2;
    }
  return room;
}

// Per base vertex, the tiles it lies in when the triangles pair as `mate`: its triangles, less one
// for each tile whose shared edge ends there.
std::vector<std::uint32_t> tilesAround(const BaseMesh& base, const Neighbours& across, const std::vector<std::uint32_t>& mate,
                                       const VertexRoom& room) {
  std::vector<std::uint32_t> tiles = room.triangles;
  for (std::uint32_t t = 0; t < base.triangleCount(); ++t)
    for (int i = 0; i < 3; ++i)
      if (across[t][i] != kNone && across[t][i] == mate[t] && t < mate[t])
        --tiles[base.triangles[t][i]], --tiles[base.triangles[t][(i + 1) % 3]];
  return tiles;
}

// Vertices in fewer tiles than they may lie in (VertexRoom) when the triangles pair as `mate`.
std::size_t countShortVertices(const BaseMesh& base, const Neighbours& across, const std::vector<std::uint32_t>& mate) {
  const VertexRoom room = vertexRoom(base, across);
  const std::vector<std::uint32_t> tiles = tilesAround(base, across, mate, room);
  std::size_t count = 0;
  for (std::uint32_t v = 0; v < base.vertexCount(); ++v) count += tiles[v] < room.fewestTiles[v];
  return count;
}

// A pair the matching may take: triangles t and o across t's edge `edge`, the quad's quality.
struct Candidate {
  std::uint32_t t, o;
  int edge;
  std::int64_t quality;
};

// The maximum-weight matching of the dual graph: per triangle its mate, or kNone. Weights in three
// tiers, each larger than any sum of the one below: a bonus, so that the matching is a largest one
// first; then keepsRoom for each pair not penalised; then the quad's quality. Pairs that would leave
// a vertex in too few tiles (VertexRoom) are penalised: first those that do so alone (the spokes of
// a vertex of three triangles), then, round by round, those the last matching used at a vertex left
// short (two tiles of four triangles). An edge weighs about 1000 n^2 (4e13 for n = 2e5 triangles),
// far inside LEMON's 64-bit weights.
std::vector<std::uint32_t> bestMatching(const BaseMesh& base, const Neighbours& across) {
  const std::uint32_t n = std::uint32_t(base.triangleCount());
  const VertexRoom room = vertexRoom(base, across);
  constexpr std::int64_t kBestQuality = 1001;
  const std::int64_t keepsRoom = kBestQuality * (n + 1), bonus = (keepsRoom + kBestQuality) * std::int64_t(n + 1);
  std::vector<Candidate> candidates;
  std::vector<bool> penalised;
  auto shortAlone = [&](std::uint32_t v) { return room.triangles[v] - 1 < room.fewestTiles[v]; };
  for (std::uint32_t t = 0; t < n; ++t)
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t o = across[t][i];
      if (o == kNone || o < t) continue;
      const auto& tri = base.triangles[t];
      const std::uint32_t p = tri[i], q = tri[(i + 1) % 3], r = tri[(i + 2) % 3];
      std::uint32_t s = kNone;
      for (const std::uint32_t v : base.triangles[o])
        if (v != p && v != q) s = v;
      const double quality = orthogonality(base.positions[p], base.positions[s], base.positions[q], base.positions[r]);
      candidates.push_back({t, o, i, 1 + std::int64_t(std::lround(1000 * quality))});
      penalised.push_back(shortAlone(p) || shortAlone(q));
    }
  std::vector<std::uint32_t> mate(n);
  constexpr int kRounds = 8;
  for (int round = 0; round < kRounds; ++round) {
    std::vector<WeightedEdge> edges;
    for (std::size_t k = 0; k < candidates.size(); ++k)
      edges.push_back({candidates[k].t, candidates[k].o, bonus + (penalised[k] ? 0 : keepsRoom) + candidates[k].quality});
    const std::vector<std::int64_t> matched = maxWeightMatching(n, edges);
    for (std::uint32_t t = 0; t < n; ++t) mate[t] = matched[t] < 0 ? kNone : std::uint32_t(matched[t]);
    const std::vector<std::uint32_t> tiles = tilesAround(base, across, mate, room);
    bool more = false;
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      const Candidate& c = candidates[k];
      if (penalised[k] || mate[c.t] != c.o) continue;
      const auto& tri = base.triangles[c.t];
      const std::uint32_t p = tri[c.edge], q = tri[(c.edge + 1) % 3];
      if (tiles[p] < room.fewestTiles[p] || tiles[q] < room.fewestTiles[q]) penalised[k] = more = true;
    }
    if (!more) break;
  }
  return mate;
}

// A triangle with a boundary edge, and that edge's first corner.
struct BoundaryCorner {
  std::uint32_t triangle;
  int corner;
};

// Frees a triangle with a boundary edge in place of the leftover t0: breadth-first over the triangles
// reachable from t0 by alternating paths (a free edge, then a matched one), re-pairing along the
// path to the first with a boundary edge. `parent`, `via` and `visited` are the search's tree, kept
// between calls and reset only where it went.
BoundaryCorner shiftToBoundary(std::uint32_t t0, const Neighbours& across, std::vector<std::uint32_t>& mate,
                               std::vector<std::uint32_t>& parent, std::vector<std::uint32_t>& via, std::vector<std::uint32_t>& visited) {
  for (const std::uint32_t t : visited) parent[t] = via[t] = kNone;
  parent.resize(across.size(), kNone), via.resize(across.size(), kNone);
  visited.assign(1, t0);
  std::queue<std::uint32_t> queue;
  queue.push(t0);
  parent[t0] = t0;
  BoundaryCorner goal{kNone, -1};
  while (!queue.empty() && goal.triangle == kNone) {
    const std::uint32_t a = queue.front();
    queue.pop();
    for (int i = 0; i < 3; ++i)
      if (across[a][i] == kNone) goal = {a, i};
    if (goal.triangle != kNone) break;
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t b = across[a][i];
      if (b == mate[a] || mate[b] == kNone || parent[mate[b]] != kNone) continue;
      parent[mate[b]] = a, via[mate[b]] = b;
      visited.push_back(mate[b]);
      queue.push(mate[b]);
    }
  }
  if (goal.triangle == kNone)
    throw Error("pairing: a leftover triangle reaches no boundary (is the base mesh manifold?)", ErrorKind::Failure);
  for (std::uint32_t c = goal.triangle; c != t0;) {  // re-pair along the path; the goal ends free
    const std::uint32_t a = parent[c], b = via[c];
    mate[a] = b, mate[b] = a;
    c = a;
  }
  mate[goal.triangle] = kNone;
  return goal;
}

// Splits the free goal's boundary edge (p, q) at its middle s, sampled from the dense surface
// through the parametrisation's history: goal = (p, s, r), a new triangle (s, q, r), the two a tile.
// The halves keep their place in the history (their frames), and the dense points mapped into the
// goal move to the half they lie in (densePoints: per base triangle, the dense vertices in it).
void splitBoundaryEdge(BaseMesh& base, const Mesh& dense, BoundaryCorner goal, Neighbours& across, std::vector<std::uint32_t>& mate,
                       std::vector<std::vector<std::uint32_t>>& densePoints) {
  const std::uint32_t g = goal.triangle;
  const int k = goal.corner;
  auto& tri = base.triangles[g];
  const std::uint32_t p = tri[k], q = tri[(k + 1) % 3], r = tri[(k + 2) % 3];
  const HistoryFrame f = base.historyFrames[g];
  const auto& fp = f.corner[k];
  const auto& fq = f.corner[(k + 1) % 3];
  const auto& fr = f.corner[(k + 2) % 3];
  const std::array<double, 3> fs{(fp[0] + fq[0]) / 2, (fp[1] + fq[1]) / 2, (fp[2] + fq[2]) / 2};
  const std::uint32_t s = std::uint32_t(base.positions.size());
  base.positions.push_back(densePosition(dense, base.history->toDense(f.version, fs)));
  base.denseVertex.push_back(-1);
  const std::uint32_t added = std::uint32_t(base.triangles.size());
  base.triangles[g] = {p, s, r};
  base.triangles.push_back({s, q, r});
  // Neighbours: goal (p, s, r) and added (s, q, r) meet at (s, r); the one across (q, r) now
  // borders added.
  const std::uint32_t acrossQR = across[g][(k + 1) % 3], acrossRP = across[g][(k + 2) % 3];
  across[g] = {kNone, added, acrossRP};
  across.push_back({kNone, acrossQR, g});
  if (acrossQR != kNone)
    for (std::uint32_t& t : across[acrossQR])
      if (t == g) t = added;
  base.historyFrames[g] = {f.version, {fp, fs, fr}};
  base.historyFrames.push_back({f.version, {fs, fq, fr}});
  mate[g] = added;
  mate.push_back(g);
  densePoints.emplace_back();
  std::vector<std::uint32_t> stay;
  for (const std::uint32_t d : densePoints[g]) {
    auto& b = base.denseBary[d];
    const double wp = b[k], wq = b[(k + 1) % 3], wr = b[(k + 2) % 3];
    if (wp >= wq) {
      b = {wp - wq, 2 * wq, wr};
      stay.push_back(d);
    } else {
      b = {2 * wp, wq - wp, wr};
      base.denseTriangle[d] = added;
      densePoints[added].push_back(d);
    }
  }
  densePoints[g] = std::move(stay);
}

// base.tiles from the mates, and the tiling's figures.
void makeTiles(BaseMesh& base, const Neighbours& across, const std::vector<std::uint32_t>& mate, PairingStats& stats) {
  base.tiles.clear();
  for (std::uint32_t t = 0; t < base.triangleCount(); ++t) {
    if (mate[t] == kNone) throw Error("pairing: a triangle was left unpaired", ErrorKind::Failure);
    if (mate[t] > t) base.tiles.push_back({t, mate[t]});
  }
  stats.shortVertices = countShortVertices(base, across, mate);
  double orthoSum = 0;
  for (std::uint32_t i = 0; i < base.tiles.size(); ++i) {
    const BaseMesh::TileCorners c = base.tileCorners(i);
    orthoSum += orthogonality(base.positions[c.p], base.positions[c.s], base.positions[c.q], base.positions[c.r]);
  }
  stats.tiles = base.tiles.size();
  stats.meanOrthogonality = stats.tiles ? orthoSum / double(stats.tiles) : 0;
}

}  // namespace

std::size_t shortVertices(const BaseMesh& base) {
  std::vector<std::uint32_t> mate(base.triangleCount(), kNone);
  for (const auto& [a, b] : base.tiles) mate[a] = b, mate[b] = a;
  return countShortVertices(base, base.triangleNeighbours(), mate);
}

PairingStats pairTriangles(BaseMesh& base, const Mesh& dense) {
  const auto start = std::chrono::steady_clock::now();
  PairingStats stats;
  Neighbours across = base.triangleNeighbours();
  std::vector<std::uint32_t> mate = bestMatching(base, across);

  // Leftovers: shift the matching to a triangle with a boundary edge, and split that edge.
  require(base.history && base.historyFrames.size() == base.triangleCount(), "pairing: the base mesh has no parametrisation history");
  std::vector<std::uint32_t> parent, via, visited;
  std::vector<std::vector<std::uint32_t>> densePoints;  // filled on the first split
  for (std::uint32_t t0 = 0; t0 < base.triangleCount(); ++t0) {
    if (mate[t0] != kNone) continue;
    if (densePoints.empty()) {
      densePoints.assign(base.triangleCount(), {});
      for (std::uint32_t d = 0; d < base.denseTriangle.size(); ++d) densePoints[base.denseTriangle[d]].push_back(d);
    }
    splitBoundaryEdge(base, dense, shiftToBoundary(t0, across, mate, parent, via, visited), across, mate, densePoints);
    ++stats.splits;
  }

  makeTiles(base, across, mate, stats);
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace isoatlas::multires
