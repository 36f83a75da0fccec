// Mesh: a polygon mesh as plain arrays (triangles, quads or mixed), positions in world mm.
// Face f's corners are faceVertices[faceOffsets[f] .. faceOffsets[f+1]).
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "core/vec.h"

namespace isoatlas {

struct Mesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;  // per vertex; empty when the mesh has none
  std::vector<std::uint32_t> faceOffsets{0};
  std::vector<std::uint32_t> faceVertices;

  std::size_t vertexCount() const { return positions.size(); }
  std::size_t faceCount() const { return faceOffsets.size() - 1; }
  std::span<const std::uint32_t> face(std::size_t f) const {
    return {faceVertices.data() + faceOffsets[f], faceOffsets[f + 1] - faceOffsets[f]};
  }
  void addFace(std::span<const std::uint32_t> corners) {
    faceVertices.insert(faceVertices.end(), corners.begin(), corners.end());
    faceOffsets.push_back(std::uint32_t(faceVertices.size()));
  }
  void addFace(std::initializer_list<std::uint32_t> corners) { addFace(std::span(corners.begin(), corners.size())); }
  bool allFacesHave(std::size_t corners) const;  // e.g. 3 for a triangle mesh
};

// The faces for which keep(f) holds, in order, with only the vertices they use (and their normals),
// renumbered in order of first use. keep is called once per face, in order.
Mesh selectFaces(const Mesh& mesh, const std::function<bool(std::size_t face)>& keep);
// All faces, without the vertices no face uses.
inline Mesh dropUnusedVertices(const Mesh& mesh) {
  return selectFaces(mesh, [](std::size_t) { return true; });
}

// The mesh with vertices of bit-identical positions merged into the first of them (normals dropped):
// triangles captured from a GPU, three corners each, become a connected mesh where they share corners.
Mesh weldIdenticalPositions(const Mesh& mesh);

// Compressed rows: row i is items[offsets[i] .. offsets[i + 1]).
struct Rows {
  std::vector<std::uint32_t> offsets, items;
  std::span<const std::uint32_t> of(std::size_t i) const { return {items.data() + offsets[i], offsets[i + 1] - offsets[i]}; }
};
// Per vertex, the faces that use it, in face order; faceOf(f) gives face f's vertices.
template <class FaceOf>
Rows vertexFaces(std::size_t vertexCount, std::size_t faceCount, const FaceOf& faceOf) {
  Rows faces;
  faces.offsets.assign(vertexCount + 1, 0);
  for (std::size_t f = 0; f < faceCount; ++f)
    for (const std::uint32_t v : faceOf(f)) ++faces.offsets[v + 1];
  for (std::size_t i = 0; i < vertexCount; ++i) faces.offsets[i + 1] += faces.offsets[i];
  faces.items.resize(faces.offsets[vertexCount]);
  std::vector<std::uint32_t> fill(faces.offsets.begin(), faces.offsets.end() - 1);
  for (std::size_t f = 0; f < faceCount; ++f)
    for (const std::uint32_t v : faceOf(f)) faces.items[fill[v]++] = std::uint32_t(f);
  return faces;
}

// Per vertex: the vertices it shares an edge with (each once), the faces that use it, and whether
// it lies on a boundary edge (an edge of one face only).
struct VertexAdjacency {
  Rows neighbours, faces;
  std::vector<char> boundary;
};
VertexAdjacency vertexAdjacency(const Mesh& mesh);

// Per triangle t and edge e (corner e to corner e + 1): the triangle that runs that edge the other
// way (its neighbour in a consistently oriented mesh), or kNoTriangle where none does (a boundary).
inline constexpr std::uint32_t kNoTriangle = ~0u;
std::vector<std::array<std::uint32_t, 3>> triangleNeighbours(std::span<const std::array<std::uint32_t, 3>> triangles);

// The mesh with each polygon split into triangles that cover it once, each turning as the polygon
// does (core/polygon_triangulation.h: a fan round a corner that sees the whole polygon, else the
// split whose smallest triangle is largest, else ear clipping); positions and normals kept. A triangle of no area maps a stretch of the model's charts
// onto one point, and one turned over folds them (mpi.off, corner_poly.off: level 10 not a manifold).
Mesh triangulated(const Mesh& mesh);

// The total area of the faces (each polygon's vector area), in the positions' units squared.
double surfaceArea(const Mesh& mesh);

// Per-vertex normals: the area-weighted sum of the faces' normals (Newell's, for polygons), normalised;
// zero where every face around the vertex is flat.
std::vector<Vec3> vertexNormals(const Mesh& mesh);

struct Box {
  Vec3 min, max;
  double diagonal() const { return norm(max - min); }
};
Box boundingBox(const std::vector<Vec3>& points);  // zero box for no points

}  // namespace isoatlas
