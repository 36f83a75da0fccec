// Volumes: round trips through every format and scalar type, geometry kept, and every kind of bad
// file rejected with an Error that names the problem.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include <zlib.h>

#include "core/error.h"
#include "core/memory_budget.h"
#include "core/volume_io.h"
#include "tests/test_util.h"

namespace isoatlas {
namespace {

using test::scratchDir;

const ScalarType kAllTypes[] = {ScalarType::UInt8, ScalarType::Int8, ScalarType::UInt16, ScalarType::Int16,
                                ScalarType::UInt32, ScalarType::Int32, ScalarType::Float32, ScalarType::Float64};

void expectSameVolume(const Volume& a, const Volume& b, bool sameType = true) {
  EXPECT_EQ(a.dims, b.dims);
  if (sameType) {
    EXPECT_EQ(a.type, b.type);
  }
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(a.spacing[i], b.spacing[i], 1e-6);
    EXPECT_NEAR(a.origin[i], b.origin[i], 1e-5);
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(a.direction.m[i][j], b.direction.m[i][j], 1e-6);
  }
  ASSERT_EQ(a.voxelCount(), b.voxelCount());
  for (std::size_t n = 0; n < a.voxelCount(); ++n) ASSERT_DOUBLE_EQ(a.value(n), b.value(n)) << "voxel " << n;
}

Mat3 rotation() {  // 30 degrees about z, then a flip of y: orthonormal, not the identity
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  Mat3 r;
  r.m = {{{c, s, 0}, {s, -c, 0}, {0, 0, 1}}};
  return r;
}

class VolumeRoundTrip : public ::testing::TestWithParam<const char*> {};

TEST_P(VolumeRoundTrip, EveryScalarTypeKeepsValuesAndGeometry) {
  const auto dir = scratchDir();
  for (ScalarType type : kAllTypes) {
    Volume v = test::rampVolume(type);
    const std::string ext = GetParam();
    if (ext.find("inr") == std::string::npos) v.direction = rotation();  // INR stores no orientation
    const std::string path = (dir / (std::string("v_") + scalarTypeName(type) + ext)).string();
    writeVolume(path, v);
    SCOPED_TRACE(path);
    expectSameVolume(v, readVolume(path));
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, VolumeRoundTrip,
                         ::testing::Values(".nii", ".nii.gz", ".nrrd", ".nhdr", ".inr", ".inr.gz"),
                         [](const auto& info) {
                           std::string s = info.param + 1;
                           for (char& c : s) c = c == '.' ? '_' : c;
                           return s;
                         });

TEST(VolumeIo, WorldCoordinatesFollowTheAffine) {
  Volume v = test::rampVolume(ScalarType::Float32);
  v.direction = rotation();
  const Vec3 ijk{2, 3, 1};
  const Vec3 w = v.indexToWorld(ijk);
  // origin + R * (spacing .* ijk), by hand
  const Vec3 scaled{2 * 0.5, 3 * 1.25, 1 * 2.0};
  const Vec3 expected = v.origin + rotation() * scaled;
  EXPECT_NEAR(w.x, expected.x, 1e-12);
  EXPECT_NEAR(w.y, expected.y, 1e-12);
  EXPECT_NEAR(w.z, expected.z, 1e-12);
  const Vec3 back = v.worldToIndex(w);
  EXPECT_NEAR(back.x, 2, 1e-12);
  EXPECT_NEAR(back.y, 3, 1e-12);
  EXPECT_NEAR(back.z, 1, 1e-12);
}

// Files written by other tools (tests/core/fixtures: nibabel 5.0 for the NIfTI files, teem's unu for
// the NRRD file; tests/core/fixtures/README.md says how): world coordinates of known voxels as those
// tools give them (nibabel's affine; the NRRD's origin and space directions, LPS turned to RAS).
struct KnownVoxel {
  std::int64_t i, j, k;
  Vec3 world;
  double value;
};
void expectKnownVoxels(const std::string& file, std::array<std::int64_t, 3> dims, const std::vector<KnownVoxel>& voxels) {
  SCOPED_TRACE(file);
  const Volume v = readVolume(std::string(ISOATLAS_SOURCE_DIR) + "/tests/core/fixtures/" + file);
  ASSERT_EQ(v.dims, dims);
  for (const KnownVoxel& k : voxels) {
    const Vec3 w = v.indexToWorld(Vec3{double(k.i), double(k.j), double(k.k)});
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(w[a], k.world[a], 1e-4) << "voxel " << k.i << "," << k.j << "," << k.k;
    EXPECT_EQ(v.value(v.index(k.i, k.j, k.k)), k.value);
  }
}

TEST(VolumeIo, FilesOfOtherToolsGiveTheirWorldCoordinates) {
  // An oblique, sheared sform (scanner), no qform.
  expectKnownVoxels("nibabel_oblique_sform.nii.gz", {5, 4, 3},
                    {{0, 0, 0, {-40.5, 22.25, -7.0}, 0},
                     {4, 1, 2, {-36.9858608544, 24.3647428751, -1.8999999985}, 49},
                     {1, 2, 1, {-40.0903416127, 24.617708534, -4.299999997}, 31}});
  // A qform alone: a rotation about z and qfac -1.
  expectKnownVoxels("nibabel_qform_only.nii", {4, 3, 5},
                    {{0, 0, 0, {10.0, -5.0, 30.0}, 0},
                     {3, 1, 2, {12.775756886, -2.572001903, 27.0}, 15.5},
                     {1, 2, 1, {10.2860182219, -3.0205572078, 28.5}, 10.5}});
  // NRRD in LPS with oblique, non-orthogonal space directions.
  expectKnownVoxels("teem_oblique_lps.nrrd", {3, 4, 2},
                    {{0, 0, 0, {-10, -20, -30}, 1000}, {2, 3, 1, {-11.2, -23.8, -28}, 1023}, {1, 0, 1, {-10.9, -20.4, -28}, 1013}});
}

TEST(VolumeIo, NrrdIsWrittenInLpsAndReadBackAsRas) {
  const auto dir = scratchDir();
  Volume v = test::rampVolume(ScalarType::UInt8);
  writeVolume((dir / "a.nrrd").string(), v);
  const std::string text = test::readBytes(dir / "a.nrrd");
  EXPECT_NE(text.find("space: left-posterior-superior"), std::string::npos);
  EXPECT_NE(text.find("space origin: (10.5,-3.25,7)"), std::string::npos) << text.substr(0, 400);
}

TEST(VolumeIo, InrRefusesAnOrientedVolume) {
  Volume v = test::rampVolume(ScalarType::UInt8);
  v.direction = rotation();
  EXPECT_THROW(writeVolume((scratchDir() / "a.inr").string(), v), Error);
}

TEST(VolumeIo, NiftiScalingIsApplied) {
  // A NIfTI file with scl_slope = 2, scl_inter = 1 reads as real values 2x + 1 (as nibabel's get_fdata).
  const auto dir = scratchDir();
  const Volume v = test::rampVolume(ScalarType::Int16);
  const auto path = dir / "scaled.nii";
  writeVolume(path.string(), v);
  std::string bytes = test::readBytes(path);
  const float slope = 2, inter = 1;
  std::memcpy(bytes.data() + 112, &slope, 4);
  std::memcpy(bytes.data() + 116, &inter, 4);
  test::writeBytes(path, bytes);
  const Volume r = readVolume(path.string());
  EXPECT_EQ(r.type, ScalarType::Float32);
  for (std::size_t n = 0; n < v.voxelCount(); ++n) ASSERT_DOUBLE_EQ(r.value(n), 2 * v.value(n) + 1);
}

// --- bad input ------------------------------------------------------------------------------

std::string errorOf(const std::string& path, const VolumeReadOptions& options = {}) {
  const Error e = test::thrownError([&] { readVolume(path, options); }, path);
  EXPECT_EQ(e.exitCode(), 2) << e.what();
  return e.what();
}

TEST(VolumeBadInput, MissingFileAndUnknownExtension) {
  EXPECT_NE(errorOf("/nonexistent/a.nii").find("no such file"), std::string::npos);
  EXPECT_NE(errorOf("a.xyz").find("unknown volume format"), std::string::npos);
}

TEST(VolumeBadInput, TruncatedFilesInEveryFormat) {
  const auto dir = scratchDir();
  const Volume v = test::rampVolume(ScalarType::Float32, {20, 20, 20});
  for (const char* ext : {".nii", ".nii.gz", ".nrrd", ".inr", ".inr.gz"}) {
    const auto path = dir / (std::string("t") + ext);
    writeVolume(path.string(), v);
    const std::string bytes = test::readBytes(path);
    test::writeBytes(path, bytes.substr(0, bytes.size() * 2 / 3));
    const std::string e = errorOf(path.string());
    EXPECT_FALSE(e.empty()) << ext;
    EXPECT_NE(e.find(path.string()), std::string::npos) << e;
  }
}

TEST(VolumeBadInput, WrongMagic) {
  const auto dir = scratchDir();
  const std::string junk(600, 'x');
  for (const char* name : {"junk.nii", "junk.nii.gz", "junk.nrrd", "junk.inr"}) {
    test::writeBytes(dir / name, junk);
    EXPECT_FALSE(errorOf((dir / name).string()).empty()) << name;
  }
  EXPECT_NE(errorOf((dir / "junk.inr").string()).find("not an INR file"), std::string::npos);
}

std::string inrHeader(const std::string& body) {
  std::string h = "#INRIMAGE-4#{\n" + body;
  h.append(256 - h.size() - 4, '\n');
  return h + "##}\n";
}

TEST(VolumeBadInput, AbsurdAndOverflowingDimensions) {
  const auto dir = scratchDir();
  test::writeBytes(dir / "huge.inr",
                   inrHeader("XDIM=1000000\nYDIM=1000000\nZDIM=1000000\nVDIM=1\nTYPE=float\nPIXSIZE=32 bits\nCPU=decm\n"));
  EXPECT_NE(errorOf((dir / "huge.inr").string()).find("voxels would take 3553 PiB, more than the memory budget"), std::string::npos);
  test::writeBytes(dir / "overflow.inr",
                   inrHeader("XDIM=4611686018427387904\nYDIM=8\nZDIM=8\nVDIM=1\nTYPE=float\nPIXSIZE=32 bits\nCPU=decm\n"));
  EXPECT_NE(errorOf((dir / "overflow.inr").string()).find("too large"), std::string::npos);
  test::writeBytes(dir / "huge.nrrd", "NRRD0004\ntype: float\ndimension: 3\nsizes: 1000000 1000000 1000000\nendian: little\nencoding: raw\n\n");
  EXPECT_NE(errorOf((dir / "huge.nrrd").string()).find("more than the memory budget"), std::string::npos);
  test::writeBytes(dir / "overflow.nrrd",
                   "NRRD0004\ntype: float\ndimension: 3\nsizes: 4294967296 4294967296 4294967296\nendian: little\nencoding: raw\n\n");
  EXPECT_FALSE(errorOf((dir / "overflow.nrrd").string()).empty());
  // NIfTI-1 dims are 16-bit: 32767^3 bytes (32 TiB) is past any budget.
  const auto nii = dir / "huge.nii";
  writeVolume(nii.string(), test::rampVolume(ScalarType::UInt8));
  std::string bytes = test::readBytes(nii);
  const std::int16_t big = 32767;
  for (int d = 1; d <= 3; ++d) std::memcpy(bytes.data() + 40 + 2 * d, &big, 2);
  test::writeBytes(nii, bytes);
  EXPECT_NE(errorOf(nii.string()).find("more than the memory budget"), std::string::npos);
  // Zero and negative sizes.
  test::writeBytes(dir / "zero.inr", inrHeader("XDIM=0\nYDIM=8\nZDIM=8\nVDIM=1\nTYPE=float\nPIXSIZE=32 bits\n"));
  EXPECT_FALSE(errorOf((dir / "zero.inr").string()).empty());
}

TEST(VolumeBadInput, UnsupportedScalarTypes) {
  const auto dir = scratchDir();
  const auto nii = dir / "complex.nii";
  writeVolume(nii.string(), test::rampVolume(ScalarType::Float64));
  std::string bytes = test::readBytes(nii);
  const std::int16_t complex64 = 32;
  std::memcpy(bytes.data() + 70, &complex64, 2);
  test::writeBytes(nii, bytes);
  EXPECT_NE(errorOf(nii.string()).find("unsupported NIfTI datatype"), std::string::npos);
  test::writeBytes(dir / "packed.inr", inrHeader("XDIM=2\nYDIM=2\nZDIM=2\nVDIM=1\nTYPE=packed\nPIXSIZE=1 bits\n"));
  EXPECT_NE(errorOf((dir / "packed.inr").string()).find("unsupported INR voxel type"), std::string::npos);
  test::writeBytes(dir / "block.nrrd", "NRRD0004\ntype: block\nblock size: 4\ndimension: 3\nsizes: 2 2 2\nendian: little\nencoding: raw\n\n" +
                                          std::string(32, '\0'));
  EXPECT_NE(errorOf((dir / "block.nrrd").string()).find("unsupported NRRD type"), std::string::npos);
  test::writeBytes(dir / "vector.inr", inrHeader("XDIM=2\nYDIM=2\nZDIM=2\nVDIM=3\nTYPE=float\nPIXSIZE=32 bits\n"));
  EXPECT_NE(errorOf((dir / "vector.inr").string()).find("VDIM"), std::string::npos);
}

// NaN and infinite voxels are read as the background, the smallest finite value, and counted; the
// other voxels are read as written.
TEST(VolumeRoundTrip, NanAndInfiniteVoxelsReadAsTheBackground) {
  const auto dir = scratchDir();
  for (const char* ext : {".nii.gz", ".nrrd", ".inr"}) {
    Volume v = test::rampVolume(ScalarType::Float32);
    const double background = valueRange(v).min;
    v.setValue(v.index(3, 2, 1), std::numeric_limits<double>::quiet_NaN());
    v.setValue(v.index(1, 1, 1), -std::numeric_limits<double>::infinity());
    const auto path = dir / (std::string("nan") + ext);
    writeVolume(path.string(), v);
    const Volume read = readVolume(path.string());
    EXPECT_EQ(read.nonFiniteVoxels, 2u) << ext;
    for (std::size_t n = 0; n < v.voxelCount(); ++n) {
      const bool hole = n == v.index(3, 2, 1) || n == v.index(1, 1, 1);
      EXPECT_EQ(read.value(n), hole ? background : v.value(n)) << ext << ", voxel " << n;
    }
  }
  Volume v = test::rampVolume(ScalarType::Float64);
  v.setValue(0, std::numeric_limits<double>::infinity());
  writeVolume((dir / "inf.nii").string(), v);
  EXPECT_EQ(readVolume((dir / "inf.nii").string()).nonFiniteVoxels, 1u);
}

TEST(VolumeBadInput, AVolumeOfNothingButNanIsRefused) {
  const auto dir = scratchDir();
  Volume v = test::rampVolume(ScalarType::Float32);
  for (std::size_t n = 0; n < v.voxelCount(); ++n) v.setValue(n, std::numeric_limits<double>::quiet_NaN());
  writeVolume((dir / "all-nan.nii").string(), v);
  EXPECT_NE(errorOf((dir / "all-nan.nii").string()).find("every voxel is NaN or infinite"), std::string::npos);
}

// A 4D NIfTI series (dimension 4 of 2) made from two ramps: each volume is read as written when
// picked; unpicked, or picked past the last, it is refused with the count; a 3D file of another
// format holds volume 0 only.
TEST(VolumeRoundTrip, OneVolumeOfA4DNiftiIsPicked) {
  const auto dir = scratchDir();
  const auto nii = dir / "4d.nii";
  const Volume first = test::rampVolume(ScalarType::UInt8);
  Volume second = first;
  for (std::size_t n = 0; n < second.voxelCount(); ++n) second.setValue(n, 200 - first.value(n));
  writeVolume(nii.string(), first);
  std::string bytes = test::readBytes(nii);
  const std::int16_t four = 4, two = 2;
  std::memcpy(bytes.data() + 40, &four, 2);
  std::memcpy(bytes.data() + 48, &two, 2);
  bytes.append(reinterpret_cast<const char*>(second.data.data()), second.data.size());
  test::writeBytes(nii, bytes);
  EXPECT_NE(errorOf(nii.string()).find("holds 2 volumes (a 4D series); pick one with --volume N"), std::string::npos);
  for (const std::int64_t volume : {0, 1}) {
    const Volume read = readVolume(nii.string(), {.volume = volume});
    EXPECT_EQ(read.dims, first.dims);
    EXPECT_EQ(read.data, (volume == 0 ? first : second).data) << "volume " << volume;
  }
  try {
    readVolume(nii.string(), {.volume = 2});
    ADD_FAILURE() << "volume 2 of 2 was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--volume 2 is past the last (1)"), std::string::npos) << e.what();
  }
  writeVolume((dir / "3d.nrrd").string(), first);
  EXPECT_EQ(readVolume((dir / "3d.nrrd").string(), {.volume = 0}).data, first.data);
  EXPECT_THROW(readVolume((dir / "3d.nrrd").string(), {.volume = 1}), Error);
}

// 4D NRRD files as 3D Slicer and teem write them, written here by hand: a diffusion series (the
// list axis first, "none" for its space direction), a sequence (the list axis last) and a file
// without a space (spacings; a time axis, a domain one, last). Each volume reads as the 3D file of
// the same header without that axis, voxel for voxel and in world space; unpicked it is refused
// with the count, and past the last with the last.
TEST(VolumeRoundTrip, OneVolumeOfA4DNrrdIsPicked) {
  const auto dir = scratchDir();
  const int nx = 5, ny = 4, nz = 3, nt = 3;
  const auto value = [](int t, int i, int j, int k) { return std::uint8_t(60 * t + i + 5 * j + 20 * k); };
  struct Layout {
    std::string name, header3, header4;
    bool seriesFirst;
  };
  const std::string space = "space: left-posterior-superior\nspace origin: (1.5,-2,7.25)\n";
  const std::string directions = "(0.9,0.1,0) (-0.2,1.1,0) (0,0.3,2.5)";
  const std::vector<Layout> layouts{
      {"dwi", space + "space directions: " + directions + "\nkinds: domain domain domain\n",
       space + "space directions: none " + directions + "\nkinds: list domain domain domain\n", true},
      {"sequence", space + "space directions: " + directions + "\nkinds: domain domain domain\n",
       space + "space directions: " + directions + " none\nkinds: domain domain domain list\n", false},
      {"spacings", "spacings: 1.5 2 2.5\n", "spacings: 1.5 2 2.5 NaN\nkinds: domain domain domain time\n", false}};
  for (const Layout& l : layouts) {
    const std::string sizes3 = std::to_string(nx) + " " + std::to_string(ny) + " " + std::to_string(nz);
    const std::string sizes4 = l.seriesFirst ? std::to_string(nt) + " " + sizes3 : sizes3 + " " + std::to_string(nt);
    std::string data4;
    for (int a = 0; a < (l.seriesFirst ? 1 : nt); ++a)
      for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
          for (int i = 0; i < nx; ++i)
            for (int b = 0; b < (l.seriesFirst ? nt : 1); ++b) data4 += char(value(l.seriesFirst ? b : a, i, j, k));
    const auto four = dir / (l.name + "_4d.nrrd");
    test::writeBytes(four, "NRRD0004\ntype: uint8\ndimension: 4\nsizes: " + sizes4 + "\n" + l.header4 + "encoding: raw\n\n" + data4);
    EXPECT_NE(errorOf(four.string()).find("holds 3 volumes (a 4D series); pick one with --volume N"), std::string::npos) << l.name;
    for (int t = 0; t < nt; ++t) {
      std::string data3;
      for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
          for (int i = 0; i < nx; ++i) data3 += char(value(t, i, j, k));
      const auto three = dir / (l.name + "_3d.nrrd");
      test::writeBytes(three, "NRRD0004\ntype: uint8\ndimension: 3\nsizes: " + sizes3 + "\n" + l.header3 + "encoding: raw\n\n" + data3);
      const Volume want = readVolume(three.string()), got = readVolume(four.string(), {.volume = t});
      EXPECT_EQ(got.dims, want.dims) << l.name;
      EXPECT_EQ(got.data, want.data) << l.name << ", volume " << t;
      for (int a = 0; a < 3; ++a) {
        EXPECT_DOUBLE_EQ(got.spacing[a], want.spacing[a]) << l.name;
        EXPECT_DOUBLE_EQ(got.origin[a], want.origin[a]) << l.name;
        for (int b = 0; b < 3; ++b) EXPECT_DOUBLE_EQ(got.direction.m[a][b], want.direction.m[a][b]) << l.name;
      }
    }
    EXPECT_NE(errorOf(four.string(), {.volume = 3}).find("--volume 3 is past the last (2)"), std::string::npos) << l.name;
  }
}

TEST(VolumeBadInput, ByteLimitIsCheckedBeforeAllocation) {
  const auto dir = scratchDir();
  writeVolume((dir / "v.nii").string(), test::rampVolume(ScalarType::Float32, {64, 64, 64}));
  const auto saved = memoryBudget();
  setMemoryBudget(1 << 19);  // the file holds 1 MiB
  EXPECT_NE(errorOf((dir / "v.nii").string()).find("would take 1 MiB, more than the memory budget of 512 KiB (--max-memory)"), std::string::npos);
  setMemoryBudget(saved);
  EXPECT_NO_THROW(readVolume((dir / "v.nii").string()));
}

// A NIfTI file whose scl_slope makes its bytes float32 is held to the limit as float32, before it
// is read: four times the bytes of its int8 voxels.
TEST(VolumeBadInput, ByteLimitHoldsForTheScaledVoxels) {
  const auto dir = scratchDir();
  const auto path = dir / "scaled.nii";
  writeVolume(path.string(), test::rampVolume(ScalarType::Int8, {64, 64, 64}));  // 256 KiB stored, 1 MiB as float32
  std::string bytes = test::readBytes(path);
  const float slope = 2, inter = 1;
  std::memcpy(bytes.data() + 112, &slope, 4);
  std::memcpy(bytes.data() + 116, &inter, 4);
  const auto saved = memoryBudget();
  setMemoryBudget(1 << 19);
  EXPECT_NO_THROW(readVolume(path.string())) << "unscaled, the file is within the limit";
  test::writeBytes(path, bytes);
  const std::string e = errorOf(path.string());
  EXPECT_NE(e.find("as float32, its scl_slope applied"), std::string::npos) << e;
  EXPECT_NE(e.find("memory budget"), std::string::npos) << e;
  setMemoryBudget(saved);
  EXPECT_NO_THROW(readVolume(path.string()));
}

// A gzip stream's contents (empty when it is no gzip stream).
std::string gunzip(const std::string& compressed) {
  z_stream z{};
  if (inflateInit2(&z, 16 + MAX_WBITS) != Z_OK) return {};
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(compressed.data()));
  z.avail_in = uInt(compressed.size());
  std::string out;
  char chunk[1 << 14];
  int status = Z_OK;
  while (status == Z_OK) {
    z.next_out = reinterpret_cast<Bytef*>(chunk);
    z.avail_out = sizeof chunk;
    status = inflate(&z, Z_NO_FLUSH);
    out.append(chunk, sizeof chunk - z.avail_out);
  }
  inflateEnd(&z);
  return status == Z_STREAM_END ? out : std::string();
}

// The committed mask pins the NIfTI writer: its voxels, grid and geometry, and the writer's bytes
// before compression (zlib's own bytes are not the writer's: another zlib may deflate differently).
TEST(VolumeIo, GoldenMaskPinsTheNiftiFormat) {
  Volume mask = Volume::zeros({7, 5, 4}, ScalarType::UInt8);
  for (std::int64_t z = 0; z < 4; ++z)
    for (std::int64_t y = 0; y < 5; ++y)
      for (std::int64_t x = 0; x < 7; ++x) mask.setValue(mask.index(x, y, z), (x * 3 + y * 5 + z * 7) % 4 == 0 ? 1 : 0);
  mask.spacing = {0.8, 0.9, 1.1};
  mask.origin = {-3, 2, 5};
  const std::string golden = std::string(ISOATLAS_SOURCE_DIR) + "/tests/core/fixtures/golden_mask.nii.gz";
  const auto dir = test::scratchDir();
  writeVolume((dir / "mask.nii.gz").string(), mask);
  test::expectGolden(golden, test::readBytes(dir / "mask.nii.gz"), gunzip);
  EXPECT_GT(gunzip(test::readBytes(golden)).size(), 348u) << "the golden is a gzip stream of a NIfTI header and its voxels";
  const Volume back = readVolume(golden);
  EXPECT_EQ(back.type, ScalarType::UInt8);
  EXPECT_EQ(back.dims, mask.dims);
  EXPECT_EQ(back.data, mask.data);
  EXPECT_NEAR(back.spacing.y, 0.9, 1e-6);
  EXPECT_NEAR(back.origin.z, 5, 1e-6);
}

}  // namespace
}  // namespace isoatlas
