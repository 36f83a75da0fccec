// Meshes: round trips through OFF, PLY (ASCII and binary) and OBJ keep positions and faces (quads
// stay quads); malformed files are rejected with an Error naming the file.
#include <gtest/gtest.h>

#include <bit>
#include <sstream>

#include "core/error.h"
#include "core/mesh_io.h"
#include "core/volume_io.h"
#include "core/mesh_topology.h"
#include "tests/test_util.h"

namespace isoatlas {
namespace {

using test::scratchDir;

void expectSameMesh(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.vertexCount(), b.vertexCount());
  ASSERT_EQ(a.faceCount(), b.faceCount());
  for (std::size_t v = 0; v < a.vertexCount(); ++v)
    for (int i = 0; i < 3; ++i) ASSERT_NEAR(a.positions[v][i], b.positions[v][i], 1e-6) << "vertex " << v;
  EXPECT_EQ(a.faceOffsets, b.faceOffsets);
  EXPECT_EQ(a.faceVertices, b.faceVertices);
}

struct Format {
  const char* ext;
  bool binary;
};

class MeshRoundTrip : public ::testing::TestWithParam<Format> {};

TEST_P(MeshRoundTrip, TrianglesAndQuadsAreKept) {
  const auto dir = scratchDir();
  const Format f = GetParam();
  for (const Mesh& mesh : {test::octahedron(), test::quadTorus(8, 6)}) {
    const std::string path = (dir / (std::to_string(mesh.faceCount()) + f.ext)).string();
    writeMesh(path, mesh, {.binary = f.binary});
    SCOPED_TRACE(path);
    const Mesh back = readMesh(path);
    expectSameMesh(mesh, back);
    const MeshTopology t = analyzeTopology(back);
    EXPECT_TRUE(t.closed);
  }
}

TEST_P(MeshRoundTrip, NormalsAreKept) {
  const Format f = GetParam();
  Mesh mesh = test::octahedron();
  for (const Vec3& p : mesh.positions) mesh.normals.push_back(p);
  const std::string path = (scratchDir() / (std::string("n") + f.ext)).string();
  writeMesh(path, mesh, {.binary = f.binary});
  const Mesh back = readMesh(path);
  ASSERT_EQ(back.normals.size(), mesh.normals.size());
  for (std::size_t v = 0; v < mesh.normals.size(); ++v)
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(back.normals[v][i], mesh.normals[v][i], 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Formats, MeshRoundTrip,
                         ::testing::Values(Format{".off", false}, Format{".ply", false}, Format{".ply", true},
                                           Format{".obj", false}),
                         [](const auto& info) {
                           return std::string(info.param.ext + 1) + (info.param.binary ? "_binary" : "_ascii");
                         });

// A VTK legacy file read back as VTK's reader reads it: the header lines (SPACE=RAS in the title),
// then POINTS, POLYGONS and the normals as big-endian float32 and int32.
struct VtkFile {
  std::vector<std::string> header;
  Mesh mesh;
};
VtkFile readVtkByHand(const std::string& path) {
  const std::string bytes = test::readBytes(path);
  std::size_t at = 0;
  auto line = [&] {
    const std::size_t end = bytes.find('\n', at);
    std::string text = bytes.substr(at, end - at);
    at = end + 1;
    return text;
  };
  auto word = [&] {
    std::uint32_t bits = 0;
    for (int k = 0; k < 4; ++k) bits = bits << 8 | std::uint8_t(bytes[at++]);
    return bits;
  };
  auto real = [&] { return double(std::bit_cast<float>(word())); };
  VtkFile f;
  for (int k = 0; k < 4; ++k) f.header.push_back(line());
  const std::size_t points = std::stoul(line().substr(7));
  for (std::size_t v = 0; v < points; ++v) f.mesh.positions.push_back({real(), real(), real()});
  line();  // the newline after the binary block
  std::istringstream polygons(line().substr(9));
  std::size_t faces = 0, size = 0;
  polygons >> faces >> size;
  for (std::size_t face = 0; face < faces; ++face) {
    std::vector<std::uint32_t> corners(word());
    for (auto& c : corners) c = word();
    f.mesh.addFace(corners);
  }
  EXPECT_EQ(size, faces + f.mesh.faceVertices.size()) << "the POLYGONS size";
  line();
  if (at < bytes.size()) {
    EXPECT_EQ(line(), "POINT_DATA " + std::to_string(points));
    EXPECT_EQ(line(), "NORMALS Normals float");
    for (std::size_t v = 0; v < points; ++v) f.mesh.normals.push_back({real(), real(), real()});
  }
  return f;
}

TEST(MeshIo, VtkLegacyHoldsTheMeshInRasForSlicer) {
  const auto dir = scratchDir();
  Mesh mesh = test::quadTorus(8, 6);
  for (const Vec3& p : mesh.positions) mesh.normals.push_back(p * 0.5);
  const std::string path = (dir / "torus.vtk").string();
  writeMesh(path, mesh);
  const VtkFile f = readVtkByHand(path);
  EXPECT_EQ(f.header[0], "# vtk DataFile Version 4.2");
  EXPECT_NE(f.header[1].find("SPACE=RAS"), std::string::npos) << "3D Slicer takes a model without it as LPS";
  EXPECT_EQ(f.header[2], "BINARY");
  EXPECT_EQ(f.header[3], "DATASET POLYDATA");
  expectSameMesh(mesh, f.mesh);
  ASSERT_EQ(f.mesh.normals.size(), mesh.normals.size());
  for (std::size_t v = 0; v < mesh.normals.size(); ++v)
    for (int i = 0; i < 3; ++i) EXPECT_EQ(f.mesh.normals[v][i], float(mesh.normals[v][i]));
  EXPECT_THROW(writeMesh((dir / "torus.stl").string(), mesh), Error);
}

// --space lps: x and y negated (positions and normals), z and the faces as they were; a .vtk says LPS.
TEST(MeshIo, LpsNegatesXAndYAndTagsTheVtk) {
  const auto dir = scratchDir();
  Mesh mesh = test::octahedron();
  for (Vec3& p : mesh.positions) p = p + Vec3{1.5, -2.25, 3};
  for (const Vec3& p : mesh.positions) mesh.normals.push_back(p);
  writeMesh((dir / "lps.ply").string(), mesh, {.space = MeshSpace::Lps});
  const Mesh back = readMesh((dir / "lps.ply").string());
  ASSERT_EQ(back.vertexCount(), mesh.vertexCount());
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    EXPECT_EQ(back.positions[v].x, -mesh.positions[v].x);
    EXPECT_EQ(back.positions[v].y, -mesh.positions[v].y);
    EXPECT_EQ(back.positions[v].z, mesh.positions[v].z);
    EXPECT_EQ(back.normals[v].x, float(-mesh.normals[v].x));
  }
  EXPECT_EQ(back.faceVertices, mesh.faceVertices) << "a half turn keeps the winding";
  writeMesh((dir / "lps.vtk").string(), mesh, {.space = MeshSpace::Lps});
  const VtkFile f = readVtkByHand((dir / "lps.vtk").string());
  EXPECT_NE(f.header[1].find("SPACE=LPS"), std::string::npos);
  EXPECT_EQ(f.mesh.positions[0].x, float(-mesh.positions[0].x));
}

TEST(MeshBadInput, AGiftiSurfaceHoldsTrianglesOnly) {
  const auto dir = scratchDir();
  const std::string path = (dir / "quads.surf.gii").string();
  try {
    writeMesh(path, test::quadTorus(8, 6));
    ADD_FAILURE() << "quads written as GIfTI";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("holds triangles"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(MeshIo, OffCommentsBlankLinesAndFaceColoursAreRead) {
  // As CGAL writes them: comments before the keyword and between sections, blank lines, colours
  // after a face's indices, a comment glued to a number.
  const auto dir = scratchDir();
  test::writeBytes(dir / "cgal.off",
                   "# Output of a CGAL tool\n#CBP\n\nOFF\n4 4 0\n\n# vertices\n0 0 0\n1 0 0 #x\n0 1 0\n0 0 1#z\n\n"
                   "3 0 2 1 .7 0 0\n3 0 1 3\n3 0 3 2 0.1 0.2 0.3\n3 1 2 3\n# End of OFF #\n");
  const Mesh m = readMesh((dir / "cgal.off").string());
  ASSERT_EQ(m.vertexCount(), 4u);
  ASSERT_EQ(m.faceCount(), 4u);
  EXPECT_EQ(m.positions[3], (Vec3{0, 0, 1}));
  EXPECT_EQ(m.faceVertices, (std::vector<std::uint32_t>{0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3}));
  EXPECT_TRUE(analyzeTopology(m).closed);
}

TEST(MeshIo, PlyObjInfoLinesAreLeftOutOfWhatOpenMeshReads) {
  // OpenMesh 9 looped forever on this header (found by fuzzing): its reader took the obj_info words
  // for keywords.
  const auto dir = scratchDir();
  test::writeBytes(dir / "info.ply",
                   "ply\nformat ascii 1.0\nobj_info float element x\nelement vertex 3\nproperty float x\n"
                   "property float y\nproperty float z\nobj_info made by hand\nelement face 1\n"
                   "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  const Mesh m = readMesh((dir / "info.ply").string());
  ASSERT_EQ(m.vertexCount(), 3u);
  ASSERT_EQ(m.faceCount(), 1u);
  EXPECT_EQ(m.positions[1], (Vec3{1, 0, 0}));
  EXPECT_EQ(m.faceVertices, (std::vector<std::uint32_t>{0, 1, 2}));
}

std::string errorOf(const std::filesystem::path& path) {
  const Error e = test::thrownError([&] { readMesh(path.string()); }, path.string());
  EXPECT_EQ(e.exitCode(), 2);
  EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  return e.what();
}

TEST(MeshBadInput, EmptyAndFacelessFiles) {
  const auto dir = scratchDir();
  test::writeBytes(dir / "empty.off", "");
  EXPECT_NE(errorOf(dir / "empty.off").find("empty file"), std::string::npos);
  test::writeBytes(dir / "points.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
  EXPECT_NE(errorOf(dir / "points.off").find("no faces"), std::string::npos);
  test::writeBytes(dir / "points.ply",
                   "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                   "end_header\n0 0 0\n");
  EXPECT_NE(errorOf(dir / "points.ply").find("no faces"), std::string::npos);
}

TEST(MeshBadInput, WrongMagicAndGarbage) {
  const auto dir = scratchDir();
  test::writeBytes(dir / "junk.off", "this is not a mesh\n");
  EXPECT_NE(errorOf(dir / "junk.off").find("not an OFF file"), std::string::npos);
  test::writeBytes(dir / "junk.ply", "plx\nformat ascii 1.0\nend_header\n");
  EXPECT_FALSE(errorOf(dir / "junk.ply").empty());
  test::writeBytes(dir / "junk.mesh", "x");
  EXPECT_NE(errorOf(dir / "junk.mesh").find("unknown mesh format"), std::string::npos);
}

TEST(MeshBadInput, BinaryOffIsRefusedWithOneLine) {
  const auto dir = scratchDir();
  std::string bytes = "OFF BINARY\n";
  for (int k = 0; k < 12; ++k) bytes += char(k % 4 == 3 ? 1 : 0);  // its counts, 1 1 1 big-endian
  test::writeBytes(dir / "binary.off", bytes);
  EXPECT_NE(errorOf(dir / "binary.off").find("binary OFF is not read"), std::string::npos);
}

TEST(MeshBadInput, CountsLargerThanTheFile) {
  const auto dir = scratchDir();
  test::writeBytes(dir / "huge.off", "OFF\n1000000000 1000000000 0\n0 0 0\n");
  EXPECT_NE(errorOf(dir / "huge.off").find("more than the file"), std::string::npos);
  test::writeBytes(dir / "huge.ply",
                   "ply\nformat binary_little_endian 1.0\nelement vertex 40000000\nproperty float x\n"
                   "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n");
  EXPECT_NE(errorOf(dir / "huge.ply").find("more than the file"), std::string::npos);
}

TEST(MeshBadInput, IndexOutOfRangeAndShortFaces) {
  const auto dir = scratchDir();
  test::writeBytes(dir / "index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  EXPECT_FALSE(errorOf(dir / "index.off").empty());
  test::writeBytes(dir / "index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  EXPECT_FALSE(errorOf(dir / "index.obj").empty());
}

TEST(MeshBadInput, NonFiniteCoordinates) {
  const auto dir = scratchDir();
  test::writeBytes(dir / "nan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n");
  EXPECT_NE(errorOf(dir / "nan.off").find("line 4: \"nan\" is not a finite number"), std::string::npos);
  test::writeBytes(dir / "bad.obj", "v 0 0 0\nv 1 x 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_NE(errorOf(dir / "bad.obj").find("line 2"), std::string::npos);
  // Binary PLY carries a real NaN: the reader passes it on, our check names the vertex.
  std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const float coords[9] = {0, 0, 0, 1, std::nanf(""), 0, 0, 1, 0};
  ply.append(reinterpret_cast<const char*>(coords), sizeof coords);
  const unsigned char three = 3;
  const std::int32_t ids[3] = {0, 1, 2};
  ply.append(reinterpret_cast<const char*>(&three), 1);
  ply.append(reinterpret_cast<const char*>(ids), sizeof ids);
  test::writeBytes(dir / "nan.ply", ply);
  EXPECT_NE(errorOf(dir / "nan.ply").find("vertex 1 has a non-finite coordinate"), std::string::npos);
}

TEST(MeshBadInput, NonManifoldIsReadAsItIsAndThenRefused) {
  // Three triangles on one edge: OpenMesh's own mesh would split it silently; we keep it and refuse it.
  const auto dir = scratchDir();
  test::writeBytes(dir / "fin.off", "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n");
  const Mesh m = readMesh((dir / "fin.off").string());
  EXPECT_EQ(m.faceCount(), 3u);
  EXPECT_EQ(m.vertexCount(), 5u);
  EXPECT_STREQ(test::thrownError([&] { requireManifold(m, "fin.off"); }, "a non-manifold mesh").what(),
               "fin.off: not 2-manifold: edge (0, 1) is shared by 3 faces");
}

}  // namespace
}  // namespace isoatlas

namespace isoatlas {
namespace {

// Inputs the fuzzers found crashing, asserting or exhausting memory in the libraries underneath;
// each must now be refused with an Error.
TEST(FuzzRegressions, EveryFoundInputIsRefusedCleanly) {
  const std::filesystem::path dir = std::filesystem::path(ISOATLAS_SOURCE_DIR) / "tests/fuzz/regressions";
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string path = entry.path().string();
    if (path.ends_with(".md")) continue;
    ++files;
    SCOPED_TRACE(path);
    const Error e = test::thrownError(
        [&] {
          if (isMeshPath(path)) requireManifold(readMesh(path), path);
          else readVolume(path);
        },
        path);
    EXPECT_EQ(e.exitCode(), 2) << e.what();
  }
  EXPECT_GE(files, 4);
}

}  // namespace
}  // namespace isoatlas
