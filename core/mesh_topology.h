// analyzeTopology: closedness, 2-manifoldness, orientation, components, Euler characteristic and
// genus of a polygon mesh, from its face lists alone (no halfedge structure), so it can check the
// output of any code that does build one.
//   manifold: every edge has one or two faces, every vertex one fan of faces, no face repeats a vertex
//   closed:   manifold and no edge has only one face
//   oriented: every two-face edge is used once in each direction
//   genus:    per component (2 - chi - boundary loops) / 2, summed; meaningful when manifold and oriented
#pragma once
#include <cstdint>
#include <map>
#include <string>

#include "core/mesh.h"

namespace isoatlas {

struct MeshTopology {
  std::size_t vertices = 0;          // vertices used by some face
  std::size_t unusedVertices = 0;    // listed but in no face
  std::size_t faces = 0, edges = 0;
  std::size_t boundaryEdges = 0, boundaryLoops = 0;
  std::size_t nonManifoldEdges = 0;  // three or more faces
  std::size_t nonManifoldVertices = 0;
  std::size_t degenerateFaces = 0;   // a face that names a vertex twice
  std::size_t components = 0;
  bool closed = false, manifold = false, oriented = false;
  long long euler = 0;  // V - E + F over used vertices
  long long genus = 0;
  std::string firstProblem;  // "edge (12, 40) is shared by 3 faces", ... ; empty when manifold
};

MeshTopology analyzeTopology(const Mesh& mesh);

// Per undirected edge (lower vertex first), how many of the faces' directed edges run along it one
// way minus the other: 0 where every edge has a partner running back, as in a closed, consistently
// oriented surface (a crack leaves an edge of one face). Edges from a vertex to itself are left out.
// Counting directions rather than faces per edge stays exact where one position is two vertices
// welded into one (several sheets meet there).
std::map<std::pair<std::uint32_t, std::uint32_t>, int> directedEdgeBalance(const Mesh& mesh);
// How many edges of directedEdgeBalance are not balanced (0: no crack).
std::size_t unbalancedEdges(const Mesh& mesh);

}  // namespace isoatlas
