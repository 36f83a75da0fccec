#include "core/mesh_topology.h"

#include <algorithm>
#include <numeric>

#include "core/union_find.h"

namespace isoatlas {
namespace {

struct HalfEdge {
  std::uint64_t key;        // (min vertex << 32) | max vertex
  std::uint32_t corner;     // index into faceVertices of the edge's first vertex
  std::uint32_t nextCorner;
  bool forward;             // first vertex is the smaller one
};

// The vertex a face names twice, or UINT32_MAX: faces are short, so pairs are compared directly.
std::uint32_t repeatedVertex(const std::uint32_t* begin, const std::uint32_t* end) {
  for (const std::uint32_t* a = begin; a != end; ++a)
    for (const std::uint32_t* b = a + 1; b != end; ++b)
      if (*a == *b) return *a;
  return UINT32_MAX;
}

// Half-edges grouped by edge (equal keys adjacent, keys ascending): a counting sort on the lower
// vertex, then each vertex's few edges in key order. Linear, where one sort of every half-edge
// dominated the analysis of a large mesh.
std::vector<HalfEdge> groupedByEdge(const std::vector<HalfEdge>& halfEdges, std::size_t vertexCount) {
  std::vector<std::uint32_t> start(vertexCount + 1, 0);
  for (const HalfEdge& h : halfEdges) ++start[(h.key >> 32) + 1];
  for (std::size_t v = 0; v < vertexCount; ++v) start[v + 1] += start[v];
  std::vector<HalfEdge> out(halfEdges.size());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (const HalfEdge& h : halfEdges) out[fill[h.key >> 32]++] = h;
  for (std::size_t v = 0; v < vertexCount; ++v)
    std::sort(out.begin() + start[v], out.begin() + start[v + 1], [](const HalfEdge& a, const HalfEdge& b) { return a.key < b.key; });
  return out;
}

}  // namespace

MeshTopology analyzeTopology(const Mesh& m) {
  MeshTopology t;
  t.faces = m.faceCount();
  const std::size_t corners = m.faceVertices.size();
  std::vector<std::uint32_t> faceOfCorner(corners);
  std::vector<HalfEdge> halfEdges;
  halfEdges.reserve(corners);
  std::vector<char> used(m.vertexCount(), 0);
  auto problem = [&](const std::string& what) {
    if (t.firstProblem.empty()) t.firstProblem = what;
  };

  for (std::size_t f = 0; f < t.faces; ++f) {
    const std::uint32_t begin = m.faceOffsets[f], end = m.faceOffsets[f + 1];
    for (std::uint32_t c = begin; c < end; ++c) {
      faceOfCorner[c] = std::uint32_t(f);
      const std::uint32_t next = c + 1 == end ? begin : c + 1;
      const std::uint32_t a = m.faceVertices[c], b = m.faceVertices[next];
      used[a] = 1;
      if (a == b) continue;
      halfEdges.push_back({(std::uint64_t(std::min(a, b)) << 32) | std::max(a, b), c, next, a < b});
    }
    const std::uint32_t twice = repeatedVertex(m.faceVertices.data() + begin, m.faceVertices.data() + end);
    if (twice != UINT32_MAX) {
      ++t.degenerateFaces;
      problem("face " + std::to_string(f) + " names vertex " + std::to_string(twice) + " twice");
    }
  }
  halfEdges = groupedByEdge(halfEdges, m.vertexCount());

  // Corners around a vertex are joined when their faces share an edge at that vertex; a manifold
  // vertex ends with all its corners in one set (one fan). Faces sharing an edge form components.
  UnionFind cornerSets(corners), faceSets(t.faces);
  std::vector<std::uint32_t> boundaryNext;  // boundary half-edges: from vertex -> to vertex
  std::vector<std::pair<std::uint32_t, std::uint32_t>> boundary;
  t.oriented = true;
  for (std::size_t i = 0; i < halfEdges.size();) {
    std::size_t j = i;
    while (j < halfEdges.size() && halfEdges[j].key == halfEdges[i].key) ++j;
    const std::size_t count = j - i;
    ++t.edges;
    const auto u = std::uint32_t(halfEdges[i].key >> 32), v = std::uint32_t(halfEdges[i].key & 0xffffffffu);
    if (count == 1) {
      ++t.boundaryEdges;
      const HalfEdge& h = halfEdges[i];
      boundary.push_back({m.faceVertices[h.corner], m.faceVertices[h.nextCorner]});
    } else if (count == 2) {
      const HalfEdge &h0 = halfEdges[i], &h1 = halfEdges[i + 1];
      if (h0.forward == h1.forward) t.oriented = false;
      // h0 runs x->y over corners (c0, n0); h1 joins the corner holding the same vertex.
      const std::uint32_t c0 = h0.corner, n0 = h0.nextCorner, c1 = h1.corner, n1 = h1.nextCorner;
      if (m.faceVertices[c0] == m.faceVertices[c1]) {
        cornerSets.unite(c0, c1);
        cornerSets.unite(n0, n1);
      } else {
        cornerSets.unite(c0, n1);
        cornerSets.unite(n0, c1);
      }
      faceSets.unite(faceOfCorner[c0], faceOfCorner[c1]);
    } else {
      ++t.nonManifoldEdges;
      problem("edge (" + std::to_string(u) + ", " + std::to_string(v) + ") is shared by " + std::to_string(count) +
              " faces");
      for (std::size_t k = i + 1; k < j; ++k) faceSets.unite(faceOfCorner[halfEdges[i].corner], faceOfCorner[halfEdges[k].corner]);
    }
    i = j;
  }

  // Fans per vertex.
  std::vector<std::uint32_t> firstRoot(m.vertexCount(), UINT32_MAX);
  std::vector<char> flagged(m.vertexCount(), 0);
  for (std::uint32_t c = 0; c < corners; ++c) {
    const std::uint32_t v = m.faceVertices[c], root = cornerSets.find(c);
    if (firstRoot[v] == UINT32_MAX) firstRoot[v] = root;
    else if (firstRoot[v] != root && !flagged[v]) {
      flagged[v] = 1;
      ++t.nonManifoldVertices;
      problem("vertex " + std::to_string(v) + " joins two or more separate fans of faces");
    }
  }

  for (char u : used) t.vertices += u ? 1 : 0;
  t.unusedVertices = m.vertexCount() - t.vertices;
  t.manifold = t.faces > 0 && t.nonManifoldEdges == 0 && t.nonManifoldVertices == 0 && t.degenerateFaces == 0;
  t.closed = t.manifold && t.boundaryEdges == 0;
  t.euler = (long long)t.vertices - (long long)t.edges + (long long)t.faces;

  std::vector<char> rootSeen(t.faces, 0);
  for (std::uint32_t f = 0; f < t.faces; ++f) {
    const std::uint32_t r = faceSets.find(f);
    if (!rootSeen[r]) rootSeen[r] = 1, ++t.components;
  }
  // Boundary loops: on a manifold mesh each boundary vertex starts exactly one boundary half-edge.
  if (t.manifold && !boundary.empty()) {
    UnionFind loops(m.vertexCount());
    for (auto [a, b] : boundary) loops.unite(a, b);
    std::vector<char> seen(m.vertexCount(), 0);
    for (auto [a, b] : boundary) {
      const std::uint32_t r = loops.find(a);
      if (!seen[r]) seen[r] = 1, ++t.boundaryLoops;
    }
  }
  t.genus = (2 * (long long)t.components - t.euler - (long long)t.boundaryLoops) / 2;
  return t;
}

std::map<std::pair<std::uint32_t, std::uint32_t>, int> directedEdgeBalance(const Mesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> balance;
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto c = mesh.face(f);
    for (std::size_t i = 0; i < c.size(); ++i) {
      const std::uint32_t a = c[i], b = c[(i + 1) % c.size()];
      if (a != b) balance[{std::min(a, b), std::max(a, b)}] += a < b ? 1 : -1;
    }
  }
  return balance;
}

std::size_t unbalancedEdges(const Mesh& mesh) {
  std::size_t count = 0;
  for (const auto& [edge, balance] : directedEdgeBalance(mesh)) count += balance != 0;
  return count;
}

}  // namespace isoatlas
