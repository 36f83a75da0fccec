// libFuzzer target for one file reader, chosen at build time by FUZZ_EXT (".nii", ".nrrd", ".inr",
// ".off", ".isoatlas", ".dvt", ".dcm", ".view" for the window's scripts, ...). The input is written to a file with that extension and read back; an isoatlas::Error
// is the expected way to fail, anything else (a crash, a sanitizer report, a hang) is a bug. What a
// reader accepts is then used as a user would use it, so that damage the parser lets through is
// reached too: a model is reconstructed at its lowest levels, a tree is sampled into a mask, an
// uncompressed NIfTI is also read in place (core/mapped_nifti.h) and must give the same floats.
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "atlas/model_file.h"
#include "atlas/reconstruct.h"
#include "core/error.h"
#include "core/mapped_nifti.h"
#include "core/image.h"
#include "core/memory_budget.h"
#include "core/mesh_io.h"
#include "core/volume_io.h"
#include "edit/dvt/dvt_file.h"
#include "edit/solids/volume_solid.h"
#ifdef FUZZ_VIEW_SCRIPT
#include "viewer/view_script.h"
#endif

namespace {
// A DICOM file is read as the series of its folder: it gets a folder of its own.
const std::string& scratchPath() {
  static const std::string path = std::string(FUZZ_EXT) == ".dcm"
                                      ? "/tmp/isoatlas-fuzz-dcm-" + std::to_string(getpid()) + "/input.dcm"
                                      : "/tmp/isoatlas-fuzz-" + std::to_string(getpid()) + FUZZ_EXT;
  return path;
}
}  // namespace

// A detached NRRD header (.nhdr) names its data file: the seeds name this one, beside the input.
constexpr const char* kNhdrData = "/tmp/isoatlas-fuzz-nhdr.raw";

// An uncompressed NIfTI read in place (MappedNifti: every row read) and into memory: where both
// accept it, they must give the same floats; a difference is a bug, as a crash is.
static void readNiftiBothWays() {
  std::optional<isoatlas::MappedNifti> mapped;
  try {
    mapped.emplace(scratchPath());
  } catch (const isoatlas::Error&) {
  }
  std::vector<float> rows;
  if (mapped) {
    const auto& d = mapped->geometry().dims;
    rows.resize(std::size_t(d[0] * d[1] * d[2]));  // at most the file's bytes: MappedNifti checked them
    for (std::int64_t z = 0; z < d[2]; ++z)
      for (std::int64_t y = 0; y < d[1]; ++y) mapped->readRow(0, y, z, d[0], rows.data() + (z * d[1] + y) * d[0]);
  }
  const isoatlas::Volume read = isoatlas::readVolume(scratchPath());
  if (!mapped) return;
  const std::vector<float> whole = read.toFloat();
  if (whole.size() != rows.size() || std::memcmp(whole.data(), rows.data(), rows.size() * sizeof(float)) != 0) {
    std::fprintf(stderr, "fuzz: the mapped NIfTI reads other floats than readVolume\n");
    std::abort();
  }
}

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // Keep every allocation far below libFuzzer's memory limit: a lying header must fail on its
  // size check or its short read, never by exhausting memory.
  isoatlas::setMemoryBudget(std::uint64_t(64) << 20);
  if (std::string(FUZZ_EXT) == ".dcm") std::filesystem::create_directories(std::filesystem::path(scratchPath()).parent_path());
  if (std::string(FUZZ_EXT) == ".nhdr") {
    std::ofstream raw(kNhdrData, std::ios::binary | std::ios::trunc);
    for (int i = 0; i < 4096; ++i) raw.put(char(i * 37));
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // Removed after each input: libFuzzer's end runs no exit handlers, and /tmp kept one file a run.
  struct RemovedAfter {
    ~RemovedAfter() { std::remove(scratchPath().c_str()); }
  } scratch;
  {
    std::ofstream out(scratchPath(), std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  try {
#ifdef FUZZ_VIEW_SCRIPT
    // Every line is checked before the window opens; what passes names its place for later errors.
    for (const isoatlas::viewer::ViewAction& a : isoatlas::viewer::readViewScript(scratchPath())) (void)a.where();
    return 0;
#endif
    if (scratchPath().ends_with(".isoatlas")) {
      // Without checksums, so damaged payloads reach the parsers and what they let through.
      const isoatlas::atlas::Model model = isoatlas::atlas::readModel(scratchPath(), {.checksums = false});
      for (int level = 0; level <= std::min(2, isoatlas::atlas::maxLevel(model.atlas)); ++level)
        isoatlas::atlas::reconstructLevel(model.base, model.atlas, level);
    } else if (scratchPath().ends_with(".dvt")) {
      const isoatlas::edit::dvt::VolumeTree tree = isoatlas::edit::dvt::readDvt(scratchPath(), false);
      // Its mask, when small enough to sample quickly (a real file's grid can be 256^3).
      const auto grid = tree.frame.grid();
      if (grid[0] * grid[1] * grid[2] <= (std::int64_t(1) << 21)) isoatlas::edit::dvt::sampleMask(tree);
    } else if (scratchPath().ends_with(".png")) {
      (void)isoatlas::readPng(scratchPath());
    } else if (isoatlas::isMeshPath(scratchPath())) {
      const isoatlas::Mesh m = isoatlas::readMesh(scratchPath());
      isoatlas::requireManifold(m, scratchPath());
    } else if (scratchPath().ends_with(".nii")) {
      readNiftiBothWays();
    } else {
      isoatlas::readVolume(scratchPath());
    }
  } catch (const isoatlas::Error&) {
  }
  return 0;
}
