#include "core/mesh_topology.h"

#include <algorithm>
#include <numeric>

#include "core/union_find.h"

namespace isoatlas {
namespace {

// A half-edge filed under the lower of its two vertices: the higher one, and the corner (index into
// faceVertices) its face leaves it from. Eight bytes, so that a large mesh's are sorted fast.
struct HalfEdge {
  std::uint32_t upper;
  std::uint32_t corner;
};

// The vertex a face names twice, or UINT32_MAX: faces are short, so pairs are compared directly.
std::uint32_t repeatedVertex(const std::uint32_t* begin, const std::uint32_t* end) {
  for (const std::uint32_t* a = begin; a != end; ++a)
    for (const std::uint32_t* b = a + 1; b != end; ++b)
      if (*a == *b) return *a;
  return UINT32_MAX;
}

// Half-edges grouped by edge: filed by lower vertex (a counting sort, `start` the offsets), then
// each vertex's few by higher vertex and corner. Linear, where one sort of every half-edge dominated
// the analysis of a large mesh.
std::vector<HalfEdge> groupedByEdge(const Mesh& m, std::vector<std::uint32_t>& start) {
  start.assign(m.vertexCount() + 1, 0);
  const auto forEachHalfEdge = [&](auto&& f) {
    for (std::size_t face = 0; face < m.faceCount(); ++face) {
      const std::uint32_t begin = m.faceOffsets[face], end = m.faceOffsets[face + 1];
      for (std::uint32_t c = begin; c < end; ++c) {
        const std::uint32_t a = m.faceVertices[c], b = m.faceVertices[c + 1 == end ? begin : c + 1];
        if (a != b) f(std::min(a, b), std::max(a, b), c);
      }
    }
  };
  forEachHalfEdge([&](std::uint32_t lower, std::uint32_t, std::uint32_t) { ++start[lower + 1]; });
  for (std::size_t v = 0; v < m.vertexCount(); ++v) start[v + 1] += start[v];
  std::vector<HalfEdge> out(start.back());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  forEachHalfEdge([&](std::uint32_t lower, std::uint32_t upper, std::uint32_t c) { out[fill[lower]++] = {upper, c}; });
  for (std::size_t v = 0; v < m.vertexCount(); ++v)
    std::sort(out.begin() + start[v], out.begin() + start[v + 1],
              [](const HalfEdge& a, const HalfEdge& b) { return a.upper != b.upper ? a.upper < b.upper : a.corner < b.corner; });
  return out;
}

}  // namespace

MeshTopology analyzeTopology(const Mesh& m) {
  MeshTopology t;
  t.faces = m.faceCount();
  const std::size_t corners = m.faceVertices.size();
  std::vector<std::uint32_t> faceOfCorner(corners);
  std::vector<char> used(m.vertexCount(), 0);
  auto problem = [&](const std::string& what) {
    if (t.firstProblem.empty()) t.firstProblem = what;
  };

  for (std::size_t f = 0; f < t.faces; ++f) {
    const std::uint32_t begin = m.faceOffsets[f], end = m.faceOffsets[f + 1];
    for (std::uint32_t c = begin; c < end; ++c) faceOfCorner[c] = std::uint32_t(f), used[m.faceVertices[c]] = 1;
    const std::uint32_t twice = repeatedVertex(m.faceVertices.data() + begin, m.faceVertices.data() + end);
    if (twice != UINT32_MAX) {
      ++t.degenerateFaces;
      problem("face " + std::to_string(f) + " names vertex " + std::to_string(twice) + " twice");
    }
  }
  std::vector<std::uint32_t> start;
  const std::vector<HalfEdge> halfEdges = groupedByEdge(m, start);
  const auto nextCorner = [&](std::uint32_t c) {
    const std::uint32_t f = faceOfCorner[c];
    return c + 1 == m.faceOffsets[f + 1] ? m.faceOffsets[f] : c + 1;
  };

  // Corners around a vertex are joined when their faces share an edge at that vertex; a manifold
  // vertex ends with all its corners in one set (one fan). Faces sharing an edge form components.
  UnionFind cornerSets(corners), faceSets(t.faces);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> boundary;
  t.oriented = true;
  for (std::uint32_t u = 0; u < m.vertexCount(); ++u)
    for (std::size_t i = start[u]; i < start[u + 1];) {
      std::size_t j = i;
      while (j < start[u + 1] && halfEdges[j].upper == halfEdges[i].upper) ++j;
      const std::size_t count = j - i;
      ++t.edges;
      const std::uint32_t v = halfEdges[i].upper;
      if (count == 1) {
        ++t.boundaryEdges;
        const std::uint32_t c = halfEdges[i].corner;
        boundary.push_back({m.faceVertices[c], m.faceVertices[nextCorner(c)]});
      } else if (count == 2) {
        // The first runs x->y over corners (c0, n0); the second joins the corner holding the same vertex.
        const std::uint32_t c0 = halfEdges[i].corner, n0 = nextCorner(c0), c1 = halfEdges[i + 1].corner, n1 = nextCorner(c1);
        if (m.faceVertices[c0] == m.faceVertices[c1]) {
          t.oriented = false;  // both run the same way
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
