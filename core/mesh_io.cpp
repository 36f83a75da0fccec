#include "core/mesh_io.h"
#include "core/mesh_gifti.h"
#include "core/mesh_vtk.h"

#include "core/atomic_file.h"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/exporter/BaseExporter.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/Mesh/BaseKernel.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/gz_file.h"
#include "core/mesh_io_validate.h"
#include "core/mesh_topology.h"

namespace isoatlas {
namespace {

using namespace OpenMesh;

// Collects what a reader finds into a Mesh, checking indices as they come.
class SoupImporter : public IO::BaseImporter {
public:
  explicit SoupImporter(Mesh& mesh) : m_(mesh) {}
  std::string error;

  VertexHandle add_vertex(const Vec3f& p) override { return add_vertex(Vec3d(p)); }
  VertexHandle add_vertex(const Vec3d& p) override {
    m_.positions.push_back({p[0], p[1], p[2]});
    return VertexHandle(int(m_.positions.size() - 1));
  }
  VertexHandle add_vertex() override { return add_vertex(Vec3d(0, 0, 0)); }
  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
  FaceHandle add_face(const VHandles& ids) override {
    if (ids.size() < 3) return fail("a face has " + std::to_string(ids.size()) + " corners (needs 3 or more)");
    corners_.clear();
    for (VertexHandle v : ids) {
      if (!v.is_valid() || std::size_t(v.idx()) >= m_.positions.size())
        return fail("a face names vertex " + std::to_string(v.idx()) + " of " + std::to_string(m_.positions.size()));
      corners_.push_back(std::uint32_t(v.idx()));
    }
    m_.addFace(corners_);
    return FaceHandle(int(m_.faceCount() - 1));
  }
  FaceHandle add_face(HalfedgeHandle) override { return fail("halfedge-based faces are not supported"); }
  void set_point(VertexHandle v, const Vec3f& p) override {
    if (inRange(v)) m_.positions[v.idx()] = {p[0], p[1], p[2]};
  }
  void set_normal(VertexHandle v, const Vec3f& n) override { set_normal(v, Vec3d(n)); }
  void set_normal(VertexHandle v, const Vec3d& n) override {
    if (!inRange(v)) return;
    if (m_.normals.size() < m_.positions.size()) m_.normals.resize(m_.positions.size());
    m_.normals[v.idx()] = {n[0], n[1], n[2]};
  }
  // Everything else a reader may report (colours, texture coordinates, status) is not kept.
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f>&) override {}
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_color(VertexHandle, const Vec3uc&) override {}
  void set_color(VertexHandle, const Vec4uc&) override {}
  void set_color(VertexHandle, const Vec3f&) override {}
  void set_color(VertexHandle, const Vec4f&) override {}
  void set_texcoord(VertexHandle, const Vec2f&) override {}
  void set_status(VertexHandle, const Attributes::StatusInfo&) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HalfedgeHandle, const Vec2f&) override {}
  void set_texcoord(VertexHandle, const Vec3f&) override {}
  void set_texcoord(HalfedgeHandle, const Vec3f&) override {}
  void set_status(HalfedgeHandle, const Attributes::StatusInfo&) override {}
  void set_color(EdgeHandle, const Vec3uc&) override {}
  void set_color(EdgeHandle, const Vec4uc&) override {}
  void set_color(EdgeHandle, const Vec3f&) override {}
  void set_color(EdgeHandle, const Vec4f&) override {}
  void set_status(EdgeHandle, const Attributes::StatusInfo&) override {}
  void set_normal(FaceHandle, const Vec3f&) override {}
  void set_normal(FaceHandle, const Vec3d&) override {}
  void set_color(FaceHandle, const Vec3uc&) override {}
  void set_color(FaceHandle, const Vec4uc&) override {}
  void set_color(FaceHandle, const Vec3f&) override {}
  void set_color(FaceHandle, const Vec4f&) override {}
  void set_status(FaceHandle, const Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}
  void reserve(unsigned int, unsigned int, unsigned int) override {}  // counts are checked against the file size instead
  size_t n_vertices() const override { return m_.positions.size(); }
  size_t n_faces() const override { return m_.faceCount(); }
  size_t n_edges() const override { return 0; }

private:
  bool inRange(VertexHandle v) const { return v.is_valid() && std::size_t(v.idx()) < m_.positions.size(); }
  FaceHandle fail(const std::string& what) {
    if (error.empty()) error = what;
    return FaceHandle();
  }
  Mesh& m_;
  std::vector<std::uint32_t> corners_;
};

// Hands a Mesh to OpenMesh's writers.
class SoupExporter : public IO::BaseExporter {
public:
  explicit SoupExporter(const Mesh& mesh) : m_(mesh) {}
  Vec3f point(VertexHandle v) const override { return Vec3f(pointd(v)); }
  Vec3d pointd(VertexHandle v) const override {
    const Vec3& p = m_.positions[v.idx()];
    return Vec3d(p.x, p.y, p.z);
  }
  bool is_point_double() const override { return false; }
  Vec3f normal(VertexHandle v) const override { return Vec3f(normald(v)); }
  Vec3d normald(VertexHandle v) const override {
    if (std::size_t(v.idx()) >= m_.normals.size()) return Vec3d(0, 0, 0);  // writers ask even without normals
    const Vec3& n = m_.normals[v.idx()];
    return Vec3d(n.x, n.y, n.z);
  }
  bool is_normal_double() const override { return false; }
  Vec3uc color(VertexHandle) const override { return Vec3uc(0, 0, 0); }
  Vec4uc colorA(VertexHandle) const override { return Vec4uc(0, 0, 0, 0); }
  Vec3ui colori(VertexHandle) const override { return Vec3ui(0, 0, 0); }
  Vec4ui colorAi(VertexHandle) const override { return Vec4ui(0, 0, 0, 0); }
  Vec3f colorf(VertexHandle) const override { return Vec3f(0, 0, 0); }
  Vec4f colorAf(VertexHandle) const override { return Vec4f(0, 0, 0, 0); }
  Vec2f texcoord(VertexHandle) const override { return Vec2f(0, 0); }
  Vec2f texcoord(HalfedgeHandle) const override { return Vec2f(0, 0); }
  Attributes::StatusInfo status(VertexHandle) const override { return {}; }
  unsigned int get_vhandles(FaceHandle f, std::vector<VertexHandle>& out) const override {
    out.clear();
    for (std::uint32_t v : m_.face(std::size_t(f.idx()))) out.push_back(VertexHandle(int(v)));
    return unsigned(out.size());
  }
  HalfedgeHandle getHeh(FaceHandle, VertexHandle) const override { return HalfedgeHandle(); }
  unsigned int get_face_texcoords(std::vector<Vec2f>&) const override { return 0; }
  Vec3f normal(FaceHandle) const override { return Vec3f(0, 0, 0); }
  Vec3d normald(FaceHandle) const override { return Vec3d(0, 0, 0); }
  Vec3uc color(FaceHandle) const override { return Vec3uc(0, 0, 0); }
  Vec4uc colorA(FaceHandle) const override { return Vec4uc(0, 0, 0, 0); }
  Vec3ui colori(FaceHandle) const override { return Vec3ui(0, 0, 0); }
  Vec4ui colorAi(FaceHandle) const override { return Vec4ui(0, 0, 0, 0); }
  Vec3f colorf(FaceHandle) const override { return Vec3f(0, 0, 0); }
  Vec4f colorAf(FaceHandle) const override { return Vec4f(0, 0, 0, 0); }
  Attributes::StatusInfo status(FaceHandle) const override { return {}; }
  Vec3uc color(EdgeHandle) const override { return Vec3uc(0, 0, 0); }
  Vec4uc colorA(EdgeHandle) const override { return Vec4uc(0, 0, 0, 0); }
  Vec3ui colori(EdgeHandle) const override { return Vec3ui(0, 0, 0); }
  Vec4ui colorAi(EdgeHandle) const override { return Vec4ui(0, 0, 0, 0); }
  Vec3f colorf(EdgeHandle) const override { return Vec3f(0, 0, 0); }
  Vec4f colorAf(EdgeHandle) const override { return Vec4f(0, 0, 0, 0); }
  Attributes::StatusInfo status(EdgeHandle) const override { return {}; }
  int get_halfedge_id(VertexHandle) override { return -1; }
  int get_halfedge_id(FaceHandle) override { return -1; }
  int get_next_halfedge_id(HalfedgeHandle) override { return -1; }
  int get_to_vertex_id(HalfedgeHandle) override { return -1; }
  int get_face_id(HalfedgeHandle) override { return -1; }
  Attributes::StatusInfo status(HalfedgeHandle) const override { return {}; }
  // The PLY writer walks the kernel's custom properties: an empty kernel has none.
  const BaseKernel* kernel() override { return &noProperties_; }
  size_t n_vertices() const override { return m_.positions.size(); }
  size_t n_faces() const override { return m_.faceCount(); }
  size_t n_edges() const override { return 0; }
  bool is_triangle_mesh() const override { return m_.allFacesHave(3); }
  bool has_vertex_normals() const override { return m_.normals.size() == m_.positions.size() && !m_.normals.empty(); }

private:
  const Mesh& m_;
  BaseKernel noProperties_;
};

void silenceOpenMesh() {
  // OpenMesh reports through its own streams; errors reach the user through our one line instead.
  omerr().disable();
  omlog().disable();
  omout().disable();
}

struct TempFile {
  std::string path;
  ~TempFile() {
    if (!path.empty()) std::remove(path.c_str());
  }
};

}  // namespace

bool isMeshPath(const std::string& path) {
  return endsWith(path, ".off") || endsWith(path, ".ply") || endsWith(path, ".obj") || endsWith(path, ".stl");
}

MeshSpace parseMeshSpace(const std::string& text, const std::string& where) {
  require(text == "ras" || text == "lps", where + ": the space is ras or lps, not '" + text + "'");
  return text == "lps" ? MeshSpace::Lps : MeshSpace::Ras;
}

bool isMeshWritePath(const std::string& path) {
  return endsWith(path, ".off") || endsWith(path, ".ply") || endsWith(path, ".obj") || endsWith(path, ".vtk") || endsWith(path, ".gii");
}

Mesh readMesh(const std::string& path) {
  require(isMeshPath(path), path + ": unknown mesh format (expected .off, .ply, .obj or .stl)");
  std::error_code ec;
  require(std::filesystem::is_regular_file(path, ec), path + ": no such file");
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  require(!ec && bytes > 0, path + ": empty file");
  std::string text;
  {
    std::ifstream file(path, std::ios::binary);
    text.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  }
  const std::string checked = validatedMeshText(path, text);
  silenceOpenMesh();
  // OpenMesh's readers take their options (normals, binary) from the file itself only when reading a
  // file by name; a normalised text goes through a temporary copy.
  std::string readPath = path;
  TempFile normalised;
  if (checked != text) {
    static std::atomic<unsigned> counter{0};  // unique per call: reads may run concurrently
    normalised.path = (std::filesystem::temp_directory_path() /
                       ("isoatlas-mesh-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) +
                        path.substr(path.rfind('.')))).string();
    std::ofstream(normalised.path, std::ios::binary) << checked;
    readPath = normalised.path;
  }

  Mesh mesh;
  SoupImporter importer(mesh);
  IO::Options options = IO::Options::VertexNormal;
  if (!IO::IOManager().read(readPath, importer, options))
    throw Error(path + ": OpenMesh could not parse it" + (importer.error.empty() ? "" : ": " + importer.error));
  if (!importer.error.empty()) throw Error(path + ": " + importer.error);
  if (!options.check(IO::Options::VertexNormal) || mesh.normals.size() != mesh.positions.size()) mesh.normals.clear();
  require(mesh.faceCount() > 0, path + ": the mesh has no faces");
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const Vec3& p = mesh.positions[v];
    require(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z),
            path + ": vertex " + std::to_string(v) + " has a non-finite coordinate");
  }
  return mesh;
}

namespace {

// The mesh as written: through OpenMesh, or as VTK legacy with the frame's tag.
void writeMeshAsItIs(const std::string& path, const Mesh& mesh, const MeshWriteOptions& options) {
  if (endsWith(path, ".vtk")) return writeVtkMesh(path, mesh, options.normals, options.space == MeshSpace::Lps ? "LPS" : "RAS");
  if (endsWith(path, ".gii")) return writeGiftiMesh(path, mesh);
  silenceOpenMesh();
  SoupExporter exporter(mesh);
  IO::Options opt;
  if (options.binary && endsWith(path, ".ply")) opt += IO::Options::Binary;
  if (options.normals && exporter.has_vertex_normals()) opt += IO::Options::VertexNormal;
  writeAtomically(path, [&](const std::string& to) {
    if (!IO::IOManager().write(to, exporter, opt, 9)) throw Error(path + ": could not write the mesh", ErrorKind::Failure);
  });
}

}  // namespace

void requireMeshSpaceFor(const std::string& path, MeshSpace space) {
  require(space == MeshSpace::Ras || !endsWith(path, ".gii"),
          path + ": a GIfTI surface is in RAS (its coordinate system says so, and FreeSurfer and Workbench read it so): leave out --space lps");
}

void writeMesh(const std::string& path, const Mesh& mesh, MeshWriteOptions options) {
  require(isMeshWritePath(path), path + ": isoatlas writes meshes as .off, .ply, .obj, .vtk or .surf.gii");
  requireMeshSpaceFor(path, options.space);
  require(mesh.faceCount() > 0, path + ": refusing to write a mesh with no faces");
  if (options.space == MeshSpace::Ras) return writeMeshAsItIs(path, mesh, options);
  Mesh lps = mesh;
  for (Vec3& p : lps.positions) p.x = -p.x, p.y = -p.y;
  for (Vec3& n : lps.normals) n.x = -n.x, n.y = -n.y;
  writeMeshAsItIs(path, lps, options);
}

void requireManifold(const Mesh& mesh, const std::string& where) {
  const MeshTopology t = analyzeTopology(mesh);
  if (!t.manifold) throw Error(where + ": not 2-manifold: " + (t.firstProblem.empty() ? "no faces" : t.firstProblem));
}

}  // namespace isoatlas
