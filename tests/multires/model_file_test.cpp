// The model file: a round trip keeps every figure; damaged files are refused with the byte offset.
#include <gtest/gtest.h>

#include "atlas/model_file.h"
#include "core/error.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"
#include "tests/multires/mesh_shapes.h"
#include "tests/test_util.h"

namespace isoatlas::atlas {
namespace {

Model torusModel() {
  Model m;
  m.chartSize = 17;
  m.dense = test::torusMesh(30, 16);
  m.base = multires::simplifyStellar(m.dense, {.vertexRatio = 0.06});
  multires::pairTriangles(m.base, m.dense);
  return m;
}

TEST(ModelFile, RoundTripKeepsEverything) {
  const auto dir = test::scratchDir();
  const Model a = torusModel();
  writeModel((dir / "t.isoatlas").string(), a);
  const Model b = readModel((dir / "t.isoatlas").string());
  EXPECT_EQ(b.chartSize, 17u);
  EXPECT_EQ(b.dense.positions, a.dense.positions);
  EXPECT_EQ(b.dense.faceVertices, a.dense.faceVertices);
  EXPECT_EQ(b.base.positions, a.base.positions);
  EXPECT_EQ(b.base.denseVertex, a.base.denseVertex);
  EXPECT_EQ(b.base.triangles, a.base.triangles);
  EXPECT_EQ(b.base.tiles, a.base.tiles);
  EXPECT_EQ(b.base.denseTriangle, a.base.denseTriangle);
  EXPECT_EQ(b.base.denseBary, a.base.denseBary);
}

TEST(ModelFile, AModelTheReaderWouldRefuseIsNotWrittenAndTheOldFileStays) {
  const auto dir = test::scratchDir();
  const std::string path = (dir / "t.isoatlas").string();
  test::writeBytes(path, "kept");
  Model badChart = torusModel();
  badChart.chartSize = 257;
  Model quads = torusModel();
  quads.dense.faceVertices.pop_back();  // the last face loses a corner: no longer all triangles
  quads.dense.faceOffsets.back() -= 1;
  for (const Model* m : {&badChart, &quads}) {
    EXPECT_THROW(writeModel(path, *m), Error);
    EXPECT_EQ(test::readBytes(path), "kept");
  }
}

TEST(ModelFile, DamagedFilesAreRefused) {
  const auto dir = test::scratchDir();
  const std::string path = (dir / "t.isoatlas").string();
  writeModel(path, torusModel());
  const std::string good = test::readBytes(path);
  auto expectRefused = [&](const std::string& bytes, const std::string& phrase) {
    test::writeBytes(path, bytes);
    try {
      readModel(path);
      ADD_FAILURE() << "accepted: " << phrase;
    } catch (const Error& e) {
      EXPECT_EQ(e.exitCode(), 2);
      EXPECT_NE(std::string(e.what()).find(phrase), std::string::npos) << e.what();
    }
  };
  expectRefused("hello", "not an isoatlas model file");
  expectRefused(good.substr(0, good.size() / 2), "runs past the end");
  std::string version = good;
  version[8] = 9;
  expectRefused(version, "format version 9");
  // A triangle corner out of range: the first corner of the dense triangles.
  std::string corner = good;
  const std::size_t denseAt = 12 + 12 + 4 + 12;  // header, HEAD section, DENS header
  const std::size_t firstCorner = denseAt + 8 + 30 * 16 * 24 + 8;
  corner[firstCorner + 3] = char(0x7f);
  expectRefused(corner, "vertex index");
  // A section given twice (here HEAD, 12 header bytes + 4): its counts would mix with the first's.
  expectRefused(good.substr(0, 28) + good.substr(12, 16) + good.substr(28), "a second HEAD section");
}

}  // namespace
}  // namespace isoatlas::atlas
