// bench/volume_io: reading the volumes of data/ with isoatlas's readers beside ITK 5.2's
// ImageFileReader (the reader ITK-SNAP and 3D Slicer build on), same files, same run. ITK reads in a
// process of its own (itk_read: its bundled nifticlib clashes with Debian's).
#include <cstdio>
#include <filesystem>
#include <memory>

#include "bench/bench_util.h"
#include "core/volume_io.h"

int main(int argc, char** argv) {
  const std::string data = argc > 1 ? argv[1] : "data";
  const auto itkRead = std::filesystem::canonical("/proc/self/exe").parent_path() / "itk_read";
  for (const char* name : {"ch2.nii.gz", "ch2better.nii.gz", "skull_2.9.inr", "liver.inr.gz"}) {
    const std::string path = data + "/volumes/" + name;
    if (!std::filesystem::exists(path)) {
      std::fprintf(stderr, "volume_io: %s missing (run scripts/fetch-data)\n", path.c_str());
      return 2;
    }
    std::size_t voxels = 0;
    const double ours = isoatlas::bench::medianSeconds(5, [&] { voxels = isoatlas::readVolume(path).voxelCount(); });
    const std::string cmd = std::string("'").append(itkRead.string()) + "' '" + path + "' 5";  // not "'" + string: GCC 12's false -Wrestrict
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
    char line[256] = {};
    if (!pipe) return 1;
    if (!std::fgets(line, sizeof line, pipe.get())) {  // Debian's ITK 5.2 has no ImageIO for INRIMAGE
      std::fprintf(stderr, "volume_io: ITK could not read %s (isoatlas: %.3f s); no row\n", name, ours);
      continue;
    }
    const auto j = nlohmann::json::parse(line);
    if (j["voxels"].get<std::size_t>() != voxels) {
      std::fprintf(stderr, "volume_io: ITK read %zu voxels of %s, isoatlas %zu\n", j["voxels"].get<std::size_t>(), name, voxels);
      return 1;
    }
    isoatlas::bench::report("volume_io", name, "read seconds", ours, "ITK 5.2 ImageFileReader<float>", j["seconds"]);
  }
  return 0;
}
