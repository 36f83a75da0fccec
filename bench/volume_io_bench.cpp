// bench/volume_io: reading the volumes of data/ with isoatlas's readers beside ITK 5.2's
// ImageFileReader (the reader ITK-SNAP and 3D Slicer build on), same files, same run.
#include <itkImage.h>
#include <itkImageFileReader.h>

#include <filesystem>

#include "bench/bench_util.h"
#include "core/volume_io.h"

int main(int argc, char** argv) {
  const std::string data = argc > 1 ? argv[1] : "data";
  for (const char* name : {"ch2.nii.gz", "ch2better.nii.gz", "skull_2.9.inr", "liver.inr.gz"}) {
    const std::string path = data + "/volumes/" + name;
    if (!std::filesystem::exists(path)) {
      std::fprintf(stderr, "volume_io: %s missing (run scripts/fetch-data)\n", path.c_str());
      return 2;
    }
    std::size_t voxels = 0;
    const double ours = isoatlas::bench::medianSeconds(5, [&] { voxels = isoatlas::readVolume(path).voxelCount(); });
    const double theirs = isoatlas::bench::medianSeconds(5, [&] {
      using Image = itk::Image<float, 3>;
      auto reader = itk::ImageFileReader<Image>::New();
      reader->SetFileName(path);
      reader->Update();
      if (reader->GetOutput()->GetLargestPossibleRegion().GetNumberOfPixels() != voxels) std::abort();
    });
    isoatlas::bench::report("volume_io", name, "read seconds", ours, "ITK 5.2 ImageFileReader<float>", theirs);
  }
  return 0;
}
