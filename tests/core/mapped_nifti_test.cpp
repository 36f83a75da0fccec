// MappedNifti: an uncompressed NIfTI read in place gives readVolume's floats voxel for voxel (every
// scalar type, either byte order, scaled, with NaN voxels, one volume of a 4D file), and refuses
// what it cannot read with an Error naming the file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/error.h"
#include "core/mapped_nifti.h"
#include "core/memory_budget.h"
#include "core/volume_io.h"
#include "tests/test_util.h"

namespace isoatlas {
namespace {

using test::scratchDir;

// Every row of the source, as readRow gives them.
std::vector<float> allRows(const VolumeSource& s) {
  const auto& d = s.geometry().dims;
  std::vector<float> out(std::size_t(d[0] * d[1] * d[2]));
  for (std::int64_t z = 0; z < d[2]; ++z)
    for (std::int64_t y = 0; y < d[1]; ++y) s.readRow(0, y, z, d[0], out.data() + (z * d[1] + y) * d[0]);
  return out;
}

// The source gives what readVolume reads, bit for bit, and the same geometry.
void expectReadsAsReadVolume(const VolumeSource& s, const Volume& read) {
  EXPECT_EQ(s.geometry().dims, read.dims);
  EXPECT_EQ(s.geometry().spacing, read.spacing);
  EXPECT_EQ(s.geometry().origin, read.origin);
  EXPECT_EQ(s.geometry().direction, read.direction);
  const std::vector<float> rows = allRows(s), whole = read.toFloat();
  ASSERT_EQ(rows.size(), whole.size());
  for (std::size_t n = 0; n < rows.size(); ++n)
    ASSERT_EQ(std::memcmp(&rows[n], &whole[n], 4), 0) << "voxel " << n << ": " << rows[n] << " against " << whole[n];
  // A row's middle alone reads as the whole row there.
  std::vector<float> part(3);
  s.readRow(2, 1, 1, 3, part.data());
  const std::size_t at = std::size_t((1 * read.dims[1] + 1) * read.dims[0] + 2);
  EXPECT_TRUE(std::equal(part.begin(), part.end(), whole.begin() + std::ptrdiff_t(at)));
}

// A NIfTI-1 file's bytes in the other byte order: each header field by its width, then the voxels.
std::string otherByteOrder(std::string b, std::size_t bytesPerVoxel) {
  auto swapAt = [&](std::size_t at, std::size_t width, std::size_t count) {
    for (std::size_t k = 0; k < count; ++k) std::reverse(b.begin() + std::ptrdiff_t(at + k * width), b.begin() + std::ptrdiff_t(at + (k + 1) * width));
  };
  swapAt(0, 4, 1);     // sizeof_hdr
  swapAt(32, 4, 1);    // extents
  swapAt(36, 2, 1);    // session_error
  swapAt(40, 2, 8);    // dim
  swapAt(56, 4, 3);    // intent_p1..3
  swapAt(68, 2, 4);    // intent_code, datatype, bitpix, slice_start
  swapAt(76, 4, 11);   // pixdim, vox_offset, scl_slope, scl_inter
  swapAt(120, 2, 1);   // slice_end
  swapAt(124, 4, 6);   // cal_max, cal_min, slice_duration, toffset, glmax, glmin
  swapAt(252, 2, 2);   // qform_code, sform_code
  swapAt(256, 4, 18);  // quatern_b .. qoffset_z, srow_x, srow_y, srow_z
  float offset;
  std::memcpy(&offset, b.data() + 108, 4);
  std::reverse(reinterpret_cast<char*>(&offset), reinterpret_cast<char*>(&offset) + 4);
  const std::size_t voxels = (b.size() - std::size_t(offset)) / bytesPerVoxel;
  swapAt(std::size_t(offset), bytesPerVoxel, voxels);
  return b;
}

Volume turnedRamp(ScalarType type) {
  Volume v = test::rampVolume(type);
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  v.direction.m = {{{c, s, 0}, {s, -c, 0}, {0, 0, 1}}};
  return v;
}

const ScalarType kAllTypes[] = {ScalarType::UInt8, ScalarType::Int8, ScalarType::UInt16, ScalarType::Int16,
                                ScalarType::UInt32, ScalarType::Int32, ScalarType::Float32, ScalarType::Float64};

TEST(MappedNifti, ReadsEveryTypeInEitherByteOrderAsReadVolumeDoes) {
  const auto dir = scratchDir();
  for (const ScalarType type : kAllTypes) {
    SCOPED_TRACE(scalarTypeName(type));
    const std::string path = (dir / "v.nii").string(), swapped = (dir / "swapped.nii").string();
    writeVolume(path, turnedRamp(type));
    test::writeBytes(swapped, otherByteOrder(test::readBytes(path), bytesPerVoxel(type)));
    for (const std::string& p : {path, swapped}) {
      const MappedNifti mapped(p);
      expectReadsAsReadVolume(mapped, readVolume(p));
      EXPECT_EQ(mapped.heldBytes(), 0u);
      EXPECT_EQ(mapped.wholeBytes(), type == ScalarType::UInt8);
    }
  }
}

TEST(MappedNifti, AppliesScalingAndReadsNonFiniteVoxelsAsTheBackground) {
  const auto dir = scratchDir();
  for (const ScalarType type : {ScalarType::Int16, ScalarType::Float64}) {
    SCOPED_TRACE(scalarTypeName(type));
    const std::string path = (dir / "scaled.nii").string();
    writeVolume(path, turnedRamp(type));
    std::string bytes = test::readBytes(path);
    const float slope = 0.37f, inter = -3;
    std::memcpy(bytes.data() + 112, &slope, 4);
    std::memcpy(bytes.data() + 116, &inter, 4);
    test::writeBytes(path, bytes);
    test::writeBytes(dir / "swapped.nii", otherByteOrder(bytes, bytesPerVoxel(type)));
    for (const std::string& p : {path, (dir / "swapped.nii").string()}) {
      const MappedNifti mapped(p);
      expectReadsAsReadVolume(mapped, readVolume(p));
      EXPECT_FALSE(mapped.wholeBytes());
    }
  }
  Volume holes = turnedRamp(ScalarType::Float32);
  holes.setValue(3, std::numeric_limits<double>::quiet_NaN());
  holes.setValue(40, std::numeric_limits<double>::infinity());
  const std::string path = (dir / "holes.nii").string();
  writeVolume(path, holes);
  const MappedNifti mapped(path);
  EXPECT_EQ(mapped.nonFiniteVoxels(), 2u);
  expectReadsAsReadVolume(mapped, readVolume(path));
  EXPECT_EQ(allRows(mapped)[3], -4.0f) << "the smallest finite value";
  // A double too large for a float is finite where readVolume judges it (as a double), so it is no
  // background: it reads as infinity in floats, both ways.
  Volume large = turnedRamp(ScalarType::Float64);
  large.setValue(5, 1e300);
  writeVolume(path, large);
  const MappedNifti mappedLarge(path);
  EXPECT_EQ(mappedLarge.nonFiniteVoxels(), 0u);
  expectReadsAsReadVolume(mappedLarge, readVolume(path));
  EXPECT_EQ(allRows(mappedLarge)[5], std::numeric_limits<float>::infinity());
}

TEST(MappedNifti, ReadsOneVolumeOfA4DFile) {
  const auto dir = scratchDir();
  const std::string path = (dir / "series.nii").string();
  const Volume first = turnedRamp(ScalarType::Int16);
  writeVolume(path, first);
  std::string bytes = test::readBytes(path);
  const std::int16_t ndim = 4, frames = 2;
  std::memcpy(bytes.data() + 40, &ndim, 2);
  std::memcpy(bytes.data() + 48, &frames, 2);
  std::string second(reinterpret_cast<const char*>(first.data.data()), first.data.size());
  for (char& c : second) c = char(c ^ 0x5a);
  test::writeBytes(path, bytes + second);
  for (const std::int64_t volume : {0, 1}) {
    SCOPED_TRACE(volume);
    expectReadsAsReadVolume(MappedNifti(path, volume), readVolume(path, {.volume = volume}));
  }
  EXPECT_THROW(MappedNifti(path, -1), Error) << "two volumes: which one must be said, as readVolume asks";
  EXPECT_THROW(MappedNifti(path, 2), Error);
}

// A .nii's header and voxels as a .hdr and .img pair (NIfTI-1's "ni1": the voxels from byte 0).
void writePair(const std::string& nii, const std::filesystem::path& hdr) {
  std::string bytes = test::readBytes(nii), header = bytes.substr(0, 348);
  float offset;
  std::memcpy(&offset, bytes.data() + 108, 4);
  const float zero = 0;
  std::memcpy(header.data() + 108, &zero, 4);
  std::memcpy(header.data() + 344, "ni1", 4);
  test::writeBytes(hdr, header);
  std::filesystem::path img = hdr;
  img.replace_extension(".img");
  test::writeBytes(img, bytes.substr(std::size_t(offset)));
}

TEST(MappedNifti, OpenVolumeSourceMapsOnlyWhatIsUncompressed) {
  const auto dir = scratchDir();
  const Volume v = turnedRamp(ScalarType::UInt16);
  writeVolume((dir / "v.nii").string(), v);
  writeVolume((dir / "v.nii.gz").string(), v);
  writeVolume((dir / "v.nrrd").string(), v);
  writePair((dir / "v.nii").string(), dir / "pair.hdr");
  for (const char* name : {"v.nii", "v.nii.gz", "v.nrrd", "pair.hdr"}) {
    SCOPED_TRACE(name);
    const std::string path = (dir / name).string();
    bool mapped = true;
    const std::shared_ptr<const VolumeSource> s = openVolumeSource(path, {}, &mapped);
    EXPECT_EQ(mapped, std::string(name) == "v.nii" || std::string(name) == "pair.hdr");
    expectReadsAsReadVolume(*s, readVolume(path));
  }
  // gzip under a .nii name: refused either way (nifticlib reads a .nii's header uncompressed).
  test::writeBytes(dir / "gzip-inside.nii", test::readBytes(dir / "v.nii.gz"));
  EXPECT_THROW(openVolumeSource((dir / "gzip-inside.nii").string()), Error);
  EXPECT_THROW(readVolume((dir / "gzip-inside.nii").string()), Error);
}

// The mapping's pages are dropped each time residentMost bytes have been read, and read back from
// the file as they are needed: the values do not change.
TEST(MappedNifti, DropsItsMappedPagesAsItReadsAndReadsTheSameValues) {
  const auto dir = scratchDir();
  const std::string path = (dir / "v.nii").string();
  const Volume v = test::rampVolume(ScalarType::Float32, {64, 64, 32});  // 512 KiB of voxels
  writeVolume(path, v);
  const NiftiLayout layout = readNiftiLayout(path, -1, false);
  const MappedNifti dropping(path, layout, 64 << 10), keeping(path, layout);
  const std::uint64_t dropsOpening = dropping.mappingDrops();  // its scan for non-finite voxels read it all once
  EXPECT_GE(dropsOpening, 7u);
  const std::vector<float> once = allRows(dropping), twice = allRows(dropping);
  EXPECT_GE(dropping.mappingDrops(), dropsOpening + 14) << "a drop every 64 KiB read";
  EXPECT_EQ(keeping.mappingDrops(), 0u);
  EXPECT_EQ(once, allRows(keeping));
  EXPECT_EQ(twice, once);
  expectReadsAsReadVolume(dropping, readVolume(path));
}

// The memory budget does not bound a mapped file (its voxels are not read into memory), but the
// file must hold every voxel its header places.
TEST(MappedNifti, RefusesAShortFileAndIgnoresTheMemoryBudget) {
  const auto dir = scratchDir();
  const std::string path = (dir / "v.nii").string();
  writeVolume(path, turnedRamp(ScalarType::Float32));
  const std::uint64_t budget = memoryBudget();
  setMemoryBudget(64);
  EXPECT_NO_THROW(MappedNifti{path});
  EXPECT_THROW(readVolume(path), Error);
  setMemoryBudget(budget);
  std::string bytes = test::readBytes(path);
  bytes.pop_back();
  test::writeBytes(path, bytes);
  const Error e = test::thrownError([&] { MappedNifti{path}; }, path);
  EXPECT_EQ(e.exitCode(), 2);
  EXPECT_NE(std::string(e.what()).find("short of the 140 float32 voxels"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  const Error missing = test::thrownError([&] { openVolumeSource((dir / "none.nii").string()); }, "none.nii");
  EXPECT_NE(std::string(missing.what()).find("no such file"), std::string::npos) << missing.what();
}

}  // namespace
}  // namespace isoatlas
