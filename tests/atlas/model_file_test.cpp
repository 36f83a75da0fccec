// The model file: a round trip keeps every figure bit for bit but the quantised atlas (within its
// reported error, borders identical); the bytes are little-endian where the format says; every
// section damaged or cut short is refused with exit 2, naming the section and the byte offset;
// version 2 files are still read; version 1 files get a line saying to rebuild them.
#include <gtest/gtest.h>

#include <cstring>

#include "atlas/make_atlas.h"
#include "atlas/model_file.h"
#include "core/error.h"
#include "core/memory_budget.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"
#include "core/mesh_io.h"
#include "tests/atlas/atlas_checks.h"
#include "tests/multires/mesh_shapes.h"
#include "tests/test_util.h"

namespace isoatlas::atlas {
namespace {

Model torusModel(bool keepDense) {
  Model m;
  m.chartSize = 17;
  Mesh dense = test::torusMesh(30, 16);
  m.base = multires::simplifyStellar(dense, {.vertexRatio = 0.06});
  multires::pairTriangles(m.base, dense);
  ChartStats stats;
  m.atlas = makeAtlas(dense, m.base, m.chartSize, &stats);
  m.coincidentTexels = stats.coincidentTexels + 7, m.gapTexels = stats.gapTexels + 3;  // non-zero, to be kept
  if (keepDense) {
    m.dense = dense;
  } else {
    m.base.denseTriangle.clear(), m.base.denseBary.clear();
  }
  return m;
}

// Every field, compared as bits, but the atlas: positions within the quantisation error the writer
// reported (and that error, a distance, within 6.5 code steps of the coarsest chart's grid: rounded to
// half a step, then moved up to 2 steps where rounding folded a triangle and 4 where it joined texels;
// a texel off the border, decoded from its own chart's codes alone, within 6.5 of that chart's steps
// along each axis), normals within the octahedral codes' angle, borders identical again.
void expectSame(const Model& a, const Model& b) {
  EXPECT_EQ(b.chartSize, a.chartSize);
  EXPECT_EQ(b.coincidentTexels, a.coincidentTexels);
  EXPECT_EQ(b.gapTexels, a.gapTexels);
  EXPECT_EQ(b.base.positions, a.base.positions);
  EXPECT_EQ(b.base.denseVertex, a.base.denseVertex);
  EXPECT_EQ(b.base.triangles, a.base.triangles);
  EXPECT_EQ(b.base.tiles, a.base.tiles);
  EXPECT_EQ(b.base.denseTriangle, a.base.denseTriangle);
  EXPECT_EQ(b.base.denseBary, a.base.denseBary);
  EXPECT_EQ(b.dense.positions, a.dense.positions);
  EXPECT_EQ(b.dense.faceVertices, a.dense.faceVertices);
  EXPECT_EQ(b.atlas.layout.charts, a.atlas.layout.charts);
  EXPECT_EQ(b.atlas.layout.columns, a.atlas.layout.columns);
  EXPECT_EQ(b.atlas.layout.rows, a.atlas.layout.rows);
  ASSERT_EQ(b.atlas.positions.size(), a.atlas.positions.size());
  const std::uint32_t n = a.atlas.layout.chartSize;
  double worst = 0, largestStep = 0;
  for (std::uint32_t c = 0; c < a.atlas.layout.charts; ++c) {
    Vec3 lo = a.atlas.position(c, 0, 0), hi = lo;
    for (std::uint32_t j = 0; j < n; ++j)
      for (std::uint32_t i = 0; i < n; ++i) {
        const Vec3 p = a.atlas.position(c, i, j);
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
        worst = std::max(worst, norm(b.atlas.position(c, i, j) - p));
        // Octahedral codes of 8 + 8 bits: within 1.2 degrees (0.93 measured at worst).
        ASSERT_GT(dot(b.atlas.normal(c, i, j), a.atlas.normal(c, i, j)), std::cos(0.021)) << "chart " << c;
      }
    const Vec3 step = (hi - lo) * (1.0 / kLargestPositionCode);
    for (std::uint32_t j = 1; j + 1 < n; ++j)
      for (std::uint32_t i = 1; i + 1 < n; ++i) {
        const Vec3 d = b.atlas.position(c, i, j) - a.atlas.position(c, i, j);
        // float boxes: a 1e-6 relative slack on the chart's extent
        ASSERT_LE(std::abs(d.x), 6.5 * step.x + 1e-6 * norm(hi - lo)) << "chart " << c << " texel (" << i << ", " << j << ") along x";
        ASSERT_LE(std::abs(d.y), 6.5 * step.y + 1e-6 * norm(hi - lo)) << "chart " << c << " texel (" << i << ", " << j << ") along y";
        ASSERT_LE(std::abs(d.z), 6.5 * step.z + 1e-6 * norm(hi - lo)) << "chart " << c << " texel (" << i << ", " << j << ") along z";
      }
    largestStep = std::max(largestStep, norm(hi - lo) / kLargestPositionCode);
  }
  EXPECT_NEAR(worst, b.quantisationError, 1e-9 * worst);
  EXPECT_GT(worst, 0);
  EXPECT_LE(worst, largestStep * 6.5 * 1.01);
  test::expectIdenticalBorders(b.base, b.atlas);
}

// Section tags and where their payloads start, read from a good file's headers.
struct Section {
  std::string tag;
  std::size_t header, payload, size;
};
std::vector<Section> sections(const std::string& bytes) {
  std::vector<Section> out;
  for (std::size_t at = 12; at < bytes.size();) {
    std::uint64_t size = 0;
    for (int i = 0; i < 8; ++i) size |= std::uint64_t(std::uint8_t(bytes[at + 4 + i])) << (8 * i);
    out.push_back({bytes.substr(at, 4), at, at + 16, size});
    at += 16 + size;
  }
  return out;
}

class ModelFileTest : public ::testing::Test {
protected:
  void SetUp() override {
    path_ = (dir_ / "t.isoatlas").string();
    writeModel(path_, torusModel(true));
    good_ = test::readBytes(path_);
  }
  void expectRefused(const std::string& bytes, const std::string& phrase) {
    test::writeBytes(path_, bytes);
    const Error e = test::thrownError([&] { readModel(path_); }, "a file that should fail with " + phrase);
    EXPECT_EQ(e.exitCode(), 2);
    EXPECT_NE(std::string(e.what()).find(phrase), std::string::npos) << e.what();
  }
  std::filesystem::path dir_ = test::scratchDir();
  std::string path_, good_;
};

TEST_F(ModelFileTest, RoundTripKeepsEverything) {
  for (const bool keep : {true, false}) {
    const Model a = torusModel(keep);
    writeModel(path_, a);
    expectSame(a, readModel(path_));
  }
}

// A model read and written back keeps its bytes at the first round (its codes are kept); one whose
// atlas changed since it was read (as a stamp changes it) is quantised afresh, the change kept.
TEST_F(ModelFileTest, AModelReadAndWrittenBackKeepsItsBytes) {
  const std::string again = (dir_ / "again.isoatlas").string();
  Model read = readModel(path_);
  writeModel(again, read);
  EXPECT_TRUE(test::readBytes(again) == good_);
  const std::size_t texel = read.atlas.layout.texel(3, 8, 8);  // inside a chart: no neighbour overwrites it
  read.atlas.positions[texel][0] += 0.05f;
  writeModel(again, read);
  const Model changed = readModel(again);
  EXPECT_NEAR(changed.atlas.positions[texel][0], read.atlas.positions[texel][0], 1e-3);
  EXPECT_NE(test::readBytes(again), good_);
}

TEST_F(ModelFileTest, WithoutTheDenseMeshTheModelIsSmaller) {
  const std::size_t withDense = good_.size();
  writeModel(path_, torusModel(false));
  EXPECT_LT(test::readBytes(path_).size(), withDense);
  for (const Section& s : sections(test::readBytes(path_))) EXPECT_TRUE(s.tag != "DENS" && s.tag != "PARA") << s.tag;
}

TEST_F(ModelFileTest, BytesAreLittleEndian) {
  // Version 4 right after the magic, then HEAD's tag, length 28, its CRC, and the chart size 17.
  EXPECT_EQ(good_.substr(0, 12), std::string("ISOATLAS\x04\0\0\0", 12));
  EXPECT_EQ(good_.substr(12, 12), std::string("HEAD\x1c\0\0\0\0\0\0\0", 12));
  EXPECT_EQ(good_.substr(28, 4), std::string("\x11\0\0\0", 4));
  // The first base vertex's x as a little-endian double.
  const Model m = torusModel(true);
  const Section base = sections(good_)[1];
  ASSERT_EQ(base.tag, "BASE");
  std::uint64_t bits = 0;
  for (int i = 0; i < 8; ++i) bits |= std::uint64_t(std::uint8_t(good_[base.payload + 8 + i])) << (8 * i);
  EXPECT_EQ(std::bit_cast<double>(bits), m.base.positions[0].x);
}

TEST_F(ModelFileTest, EverySectionDamagedOrCutShortIsRefusedByName) {
  const std::vector<Section> all = sections(good_);
  ASSERT_EQ(all.size(), 6u);  // HEAD BASE HALF ATLS DENS PARA
  for (const Section& s : all) {
    std::string damaged = good_;
    damaged[s.payload + s.size / 2] ^= 0x20;
    expectRefused(damaged, "section " + s.tag + ", byte " + std::to_string(s.payload) + ": checksum mismatch");
    expectRefused(good_.substr(0, s.payload + s.size / 2), "section " + s.tag + ", byte " + std::to_string(s.payload) + ": runs past");
    expectRefused(good_.substr(0, s.header + 7), "truncated section header");
    if (s.tag != "DENS" && s.tag != "PARA")  // without both, the model is whole but lacks no required part
      expectRefused(good_.substr(0, s.header) + good_.substr(s.payload + s.size), s.tag + " section");
  }
  expectRefused("hello", "not an isoatlas model file");
}

TEST_F(ModelFileTest, ParsersCheckWhatTheChecksumWouldMiss) {
  // With checksums off (as the fuzzer reads), damage must still be caught by the parsers.
  const std::vector<Section> all = sections(good_);
  std::string corner = good_;
  const Section& base = all[1];
  const Model m = torusModel(true);
  const std::size_t firstCorner = base.payload + 8 + m.base.vertexCount() * 32 + 8;
  corner[firstCorner + 3] = char(0x7f);
  test::writeBytes(path_, corner);
  const Error outOfRange = test::thrownError([&] { readModel(path_, {.checksums = false}); }, "a corner out of range");
  EXPECT_NE(std::string(outOfRange.what()).find("section BASE, byte " + std::to_string(firstCorner + 4) + ": base vertex index"),
            std::string::npos)
      << outOfRange.what();
  // A base triangle naming one vertex twice (the first triangle's second corner made its first).
  std::string twice = good_;
  for (int i = 0; i < 4; ++i) twice[firstCorner + 4 + i] = twice[firstCorner + i];
  test::writeBytes(path_, twice);
  const Error twiceError = test::thrownError([&] { readModel(path_, {.checksums = false}); }, "a triangle naming a vertex twice");
  EXPECT_NE(std::string(twiceError.what()).find("names a vertex twice"), std::string::npos) << twiceError.what();
  std::string halfedge = good_;
  halfedge[all[2].payload + 4] ^= 1;  // the first halfedge's start u
  test::writeBytes(path_, halfedge);
  EXPECT_THROW(readModel(path_, {.checksums = false}), Error);
  // A chart's packed codes damaged (the first chart's deflated bytes, past its box and length): they
  // no longer inflate to its texels, said in one line.
  const Section& atlasSection = all[3];
  ASSERT_EQ(atlasSection.tag, "ATLS");
  std::string codes = good_;
  for (std::size_t k = atlasSection.payload + 12 + 24 + 4; k < atlasSection.payload + 12 + 24 + 12; ++k) codes[k] = char(~codes[k]);
  test::writeBytes(path_, codes);
  const Error codesError = test::thrownError([&] { readModel(path_, {.checksums = false}); }, "damaged chart codes");
  EXPECT_NE(std::string(codesError.what()).find("section ATLS, byte"), std::string::npos) << codesError.what();
  EXPECT_NE(std::string(codesError.what()).find("do not inflate"), std::string::npos) << codesError.what();
  // A section given twice: its counts would mix with the first's.
  const Section& head = all[0];
  expectRefused(good_.substr(0, head.payload + head.size) + good_.substr(head.header, 16 + head.size) +
                    good_.substr(head.payload + head.size),
                "a second HEAD section");
}

TEST_F(ModelFileTest, OtherVersionsAndUnknownSections) {
  std::string v1 = good_;
  v1[8] = 1;
  expectRefused(v1, "version 1 holds no atlas; build the model again");
  std::string v9 = good_;
  v9[8] = 9;
  expectRefused(v9, "format version 9 (this isoatlas reads versions 2, 3 and 4)");
  // A section of a later version is skipped.
  std::string extra = good_ + std::string("NEWS\x03\0\0\0\0\0\0\0", 12);
  const char payload[] = "abc";
  const std::uint32_t sum = 0x352441c2;  // CRC-32 of "abc"
  for (int i = 0; i < 4; ++i) extra.push_back(char((sum >> (8 * i)) & 0xff));
  extra += payload;
  test::writeBytes(path_, extra);
  expectSame(torusModel(true), readModel(path_));
}

// A version 2 file (written by the isoatlas before quantisation, kept in tests/atlas/data) is still
// read: its float atlas as it was, every border identical, and it measures as its dense mesh's model.
TEST(ModelFile, AVersionTwoFileIsStillRead) {
  const std::string dir = ISOATLAS_TEST_DATA_DIR;
  const Model m = readModel(dir + "/torus_v2.isoatlas");
  EXPECT_EQ(m.chartSize, 5u);
  EXPECT_EQ(m.quantisationError, 0);
  EXPECT_EQ(m.atlas.layout.charts, m.base.tiles.size());
  test::expectIdenticalBorders(m.base, m.atlas);
  const Mesh dense = readMesh(dir + "/torus_v2_dense.off");
  for (std::uint32_t c = 0; c < m.atlas.layout.charts; ++c)
    for (std::uint32_t j = 0; j < 5; ++j)
      for (std::uint32_t i = 0; i < 5; ++i) {
        const Vec3 p = m.atlas.position(c, i, j);
        // Within the dense mesh's sagitta: 12 segments round the tube, 24 round the axis.
        EXPECT_LT(std::abs(std::hypot(std::hypot(p.x, p.y) - 3, p.z) - 1), 1 - std::cos(M_PI / 12) + 4 * (1 - std::cos(M_PI / 24)));
      }
  EXPECT_EQ(dense.vertexCount(), 288u);
}

// The committed version-4 model pins the format: what it holds, and the writer's bytes for it. It
// was written from the committed version-3 model (read, then written as it came): a version 3 file
// is still read, and its 16-bit codes are kept as they were (the same atlas from both files).
void expectTorusGoldenContents(const Model& m) {
  EXPECT_EQ(m.chartSize, 5u);
  EXPECT_EQ(m.atlas.layout.charts, 14u);
  EXPECT_EQ(m.base.vertexCount(), 14u);
  EXPECT_EQ(m.base.triangleCount(), 28u);
  const Vec3 p = m.atlas.position(0, 0, 0);
  EXPECT_NEAR(p.x, 2.733693, 1e-6);
  EXPECT_NEAR(p.y, 2.733693, 1e-6);
  EXPECT_NEAR(p.z, -0.5, 1e-6);
}

TEST(ModelFile, GoldenVersionFourModelPinsTheFormat) {
  const std::string golden = std::string(ISOATLAS_TEST_DATA_DIR) + "/torus_v4.isoatlas";
  const Model m = readModel(golden);
  expectTorusGoldenContents(m);
  const auto dir = test::scratchDir();
  writeModel((dir / "m.isoatlas").string(), m);
  test::expectGolden(golden, test::readBytes(dir / "m.isoatlas"));
}

// The quantiser pinned: a model without codes (version 2 holds floats) is quantised as it is
// written, so the golden fixes each chart's box, step and rounding, the normals' octahedral codes,
// the prediction and the packing (the version-4 golden above only re-emits the codes it read).
TEST(ModelFile, GoldenQuantisedModelPinsTheQuantiser) {
  const std::string data = ISOATLAS_TEST_DATA_DIR;
  const Model floats = readModel(data + "/torus_v2.isoatlas");
  ASSERT_TRUE(floats.codes.empty());
  const auto dir = test::scratchDir();
  const double moved = writeModel((dir / "m.isoatlas").string(), floats);
  EXPECT_GT(moved, 0);
  test::expectGolden(data + "/torus_v2_quantised.isoatlas", test::readBytes(dir / "m.isoatlas"));
}

// A version-4 model's deflated charts inflate a thousandfold: held to the memory budget from the
// chart count and size, before any is unpacked.
TEST(ModelFile, AModelsChartsAreHeldToTheMemoryBudgetBeforeTheyInflate) {
  const std::string golden = std::string(ISOATLAS_TEST_DATA_DIR) + "/torus_v4.isoatlas";
  const std::uint64_t saved = memoryBudget();
  setMemoryBudget(4096);  // 14 charts of 5 x 5 texels take about 9 KiB
  std::string message;
  try {
    readModel(golden);
  } catch (const Error& e) {
    message = e.what();
  }
  setMemoryBudget(saved);
  EXPECT_NE(message.find("torus_v4.isoatlas: the atlas's 14 charts of 5 x 5 texels would take 9.3 KiB, more than the memory budget of 4 KiB"),
            std::string::npos)
      << message;
  EXPECT_NO_THROW(readModel(golden));
}

TEST(ModelFile, AVersionThreeFileIsStillReadAndKeepsItsCodes) {
  const std::string data = ISOATLAS_TEST_DATA_DIR;
  const Model v3 = readModel(data + "/torus_v3.isoatlas"), v4 = readModel(data + "/torus_v4.isoatlas");
  expectTorusGoldenContents(v3);
  EXPECT_EQ(v3.atlas.positions, v4.atlas.positions);
  EXPECT_EQ(v3.atlas.normals, v4.atlas.normals);
  EXPECT_EQ(v3.quantisationError, v4.quantisationError);
  const auto dir = test::scratchDir();
  writeModel((dir / "m.isoatlas").string(), v3);
  EXPECT_TRUE(test::readBytes(dir / "m.isoatlas") == test::readBytes(data + "/torus_v4.isoatlas"));
}

// Packed codes come back exactly, whatever they are: every code of the full 16 bits (version 3's
// width), neighbours far apart so that the predictions wrap round, and a chart of constant codes.
TEST(ModelFile, PackedChartCodesComeBackExactly) {
  const std::uint32_t n = 17;
  std::uint64_t state = 12345;
  auto next = [&] { return state = state * 6364136223846793005ull + 1442695040888963407ull, std::uint32_t(state >> 33); };
  for (int kind = 0; kind < 2; ++kind) {
    QuantisedChart chart;
    for (std::uint32_t k = 0; k < n * n; ++k) {
      const std::uint32_t r = kind == 0 ? next() : 7;
      chart.positions.push_back({std::uint16_t(r), std::uint16_t(k % 2 ? 0 : 65535), std::uint16_t(r >> 16)});
      chart.normals.push_back({std::uint8_t(r >> 8), std::uint8_t(k % 3 ? 255 : 0)});
    }
    const std::vector<std::uint8_t> packed = packChartCodes(chart, n);
    QuantisedChart back;
    ASSERT_TRUE(unpackChartCodes(packed.data(), packed.size(), n, back));
    EXPECT_EQ(back.positions, chart.positions) << "kind " << kind;
    EXPECT_EQ(back.normals, chart.normals) << "kind " << kind;
    EXPECT_FALSE(unpackChartCodes(packed.data(), packed.size(), n + 1, back)) << "inflates to another chart size";
  }
}

TEST_F(ModelFileTest, AModelTheReaderWouldRefuseIsNotWrittenAndTheOldFileStays) {
  test::writeBytes(path_, "kept");
  Model badChart = torusModel(false);
  badChart.chartSize = 257;
  Model noAtlas = torusModel(false);
  noAtlas.atlas = {};
  Model denseWithoutParametrisation = torusModel(false);
  denseWithoutParametrisation.dense = test::torusMesh(30, 16);
  for (const Model* m : {&badChart, &noAtlas, &denseWithoutParametrisation}) {
    EXPECT_THROW(writeModel(path_, *m), Error);
    EXPECT_EQ(test::readBytes(path_), "kept");
  }
}

}  // namespace
}  // namespace isoatlas::atlas
