// writeAtomically and the writers built on it: a file appears whole or not at all, and a write that
// fails leaves the old file as it was and no temporary behind.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image.h"
#include "core/mesh_io.h"
#include "core/sectioned_file.h"
#include "core/volume_io.h"
#include "tests/test_util.h"

namespace isoatlas {
namespace {

std::size_t entries(const std::filesystem::path& dir) {
  return std::size_t(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()));
}

TEST(AtomicFile, TheTemporaryKeepsTheNameSoTheExtensionStillChoosesTheFormat) {
  const std::string t = temporaryPathFor("/some/dir/mask.nii.gz");
  EXPECT_EQ(std::filesystem::path(t).parent_path(), "/some/dir");
  EXPECT_TRUE(t.ends_with(".partial.mask.nii.gz")) << t;
  EXPECT_NE(temporaryPathFor("/some/dir/mask.nii.gz"), t) << "each call its own name";
}

TEST(AtomicFile, AWholeWriteReplacesTheFileAndLeavesNoTemporary) {
  const auto dir = test::scratchDir();
  const auto path = (dir / "a.txt").string();
  test::writeBytes(path, "old");
  writeFileAtomically(path, "new contents");
  EXPECT_EQ(test::readBytes(path), "new contents");
  EXPECT_EQ(entries(dir), 1u);
}

// What a killed writer left (a temporary of a process of this host that is gone) goes with the next
// whole write of that file; a live process's temporary, another file's, and another host's (whose
// pid says nothing here) stay.
TEST(AtomicFile, AWholeWriteRemovesTheTemporariesOfWritersThatAreGone) {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ASSERT_EQ(::waitpid(child, nullptr, 0), child);  // reaped: its pid names no process now
  const auto dir = test::scratchDir();
  const auto path = (dir / "a.txt").string();
  const std::string ours = std::filesystem::path(temporaryPathFor(path)).filename().string();
  const std::string host = ours.substr(ours.find('@'), ours.find(".partial.") - ours.find('@'));  // "@<host>"
  ASSERT_GT(host.size(), 1u) << ours;
  const std::string gone = "." + std::to_string(child) + "-3" + host + ".partial.a.txt";
  const std::string live = "." + std::to_string(::getpid()) + "-9999" + host + ".partial.a.txt";
  const std::string other = "." + std::to_string(child) + "-3" + host + ".partial.b.txt";
  const std::string elsewhere = "." + std::to_string(child) + "-3@another-host.partial.a.txt";
  for (const std::string& name : {gone, live, other, elsewhere}) test::writeBytes((dir / name).string(), "half");
  writeFileAtomically(path, "whole");
  EXPECT_FALSE(std::filesystem::exists(dir / gone));
  EXPECT_TRUE(std::filesystem::exists(dir / live));
  EXPECT_TRUE(std::filesystem::exists(dir / other));
  EXPECT_TRUE(std::filesystem::exists(dir / elsewhere)) << "another host's writer may be live";
  EXPECT_EQ(test::readBytes(path), "whole");
}

TEST(AtomicFile, AFailedWriteLeavesTheOldFileAndNoTemporary) {
  const auto dir = test::scratchDir();
  const auto path = (dir / "a.txt").string();
  test::writeBytes(path, "old");
  EXPECT_THROW(writeAtomically(path,
                               [](const std::string& temporary) {
                                 test::writeBytes(temporary, "half");
                                 throw Error("the writer failed half way");
                               }),
               Error);
  EXPECT_EQ(test::readBytes(path), "old");
  EXPECT_EQ(entries(dir), 1u);
}

TEST(AtomicFile, EveryWriterGoesThroughATemporary) {
  // Each writer leaves only its file in the folder (its temporary renamed) and reads back.
  const auto dir = test::scratchDir();
  const Volume v = test::rampVolume(ScalarType::UInt8);
  for (const char* name : {"v.nii.gz", "v.nrrd", "v.inr.gz"}) {
    writeVolume((dir / name).string(), v);
    EXPECT_EQ(readVolume((dir / name).string()).data, v.data) << name;
  }
  writeMesh((dir / "m.ply").string(), test::octahedron());
  EXPECT_EQ(readMesh((dir / "m.ply").string()).faceCount(), 8u);
  writePng((dir / "i.png").string(), Image(4, 3, 3));
  EXPECT_EQ(readPng((dir / "i.png").string()).width, 4);
  EXPECT_EQ(entries(dir), 5u) << "no temporaries left";
}

TEST(AtomicFile, AWriterThatCannotWriteNamesThePathNotTheTemporary) {
  const std::string path = (test::scratchDir() / "no-such-folder" / "v.nii.gz").string();
  const std::string message =
      test::thrownError([&] { writeVolume(path, test::rampVolume(ScalarType::UInt8)); }, "a write into a missing folder").what();
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_EQ(message.find(".partial."), std::string::npos) << message;
  EXPECT_NE(message.find("folder does not exist"), std::string::npos) << message;
}

TEST(AtomicFile, AnUnfinishedSectionedFileLeavesTheOldOne) {
  const auto dir = test::scratchDir();
  const auto path = (dir / "f.bin").string();
  test::writeBytes(path, "old");
  const char magic[8] = {'T', 'E', 'S', 'T', 'F', 'I', 'L', 'E'};
  {
    SectionedFileWriter out(path, magic, 1);
    SectionWriter payload;
    payload.put(std::uint32_t(7));
    out.section("DATA", payload);
    // destroyed without finish(): an error while writing
  }
  EXPECT_EQ(test::readBytes(path), "old");
  EXPECT_EQ(entries(dir), 1u);
  {
    SectionedFileWriter out(path, magic, 1);
    out.finish();
  }
  EXPECT_EQ(test::readBytes(path).substr(0, 8), "TESTFILE");
  EXPECT_EQ(entries(dir), 1u);
}

}  // namespace
}  // namespace isoatlas
