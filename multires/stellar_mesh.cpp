#include "multires/stellar_mesh.h"

#include <OpenMesh/Core/System/omstream.hh>

#include "core/error.h"
#include "core/mesh_topology.h"

namespace isoatlas::multires {

StellarMesh toStellarMesh(const Mesh& mesh, const std::string& where) {
  require(mesh.faceCount() > 0, where + ": the mesh has no faces");
  require(mesh.allFacesHave(3), where + ": the multiresolution stage takes triangle meshes only");
  const MeshTopology topology = analyzeTopology(mesh);
  require(topology.manifold, where + ": not 2-manifold: " + topology.firstProblem);
  require(topology.oriented, where + ": the faces are not consistently oriented");
  require(topology.unusedVertices == 0,
          where + ": " + std::to_string(topology.unusedVertices) + " vertices belong to no face");

  StellarMesh out;
  out.reserve(mesh.vertexCount(), mesh.faceCount() * 3 / 2 + 8, mesh.faceCount());
  for (const Vec3& p : mesh.positions) out.add_vertex(toPoint(p));
  // analyzeTopology has already named any problem; OpenMesh's own messages stay off meanwhile.
  struct QuietOpenMesh {
    QuietOpenMesh() { omerr().disable(); }
    ~QuietOpenMesh() { omerr().enable(); }
  } quiet;
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto c = mesh.face(f);
    const FaceH fh = out.add_face(VertexH(int(c[0])), VertexH(int(c[1])), VertexH(int(c[2])));
    if (!fh.is_valid())
      throw Error(where + ": face " + std::to_string(f) + " cannot join the halfedge mesh (complex vertex or edge)");
  }
  return out;
}

Mesh toMesh(const StellarMesh& mesh) {
  Mesh out;
  std::vector<std::uint32_t> index(mesh.n_vertices(), ~0u);
  for (const VertexH v : mesh.vertices()) {
    index[v.idx()] = std::uint32_t(out.positions.size());
    out.positions.push_back(toVec3(mesh.point(v)));
  }
  for (const FaceH f : mesh.faces()) {
    std::uint32_t c[3];
    int i = 0;
    for (const VertexH v : mesh.fv_range(f)) c[i++] = index[v.idx()];
    out.addFace({c[0], c[1], c[2]});
  }
  return out;
}

}  // namespace isoatlas::multires
