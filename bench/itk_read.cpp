// itk_read FILE RUNS: median seconds of ITK 5.2's ImageFileReader<float> on FILE, as one JSON
// line. Its own process: ITK bundles a nifticlib whose symbols clash with Debian's libnifti2, which
// isoatlas links, so the two readers cannot share a process.
#include <itkImage.h>
#include <itkImageFileReader.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: itk_read FILE RUNS\n");
    return 2;
  }
  using Image = itk::Image<float, 3>;
  std::vector<double> t;
  unsigned long long voxels = 0;
  for (int i = 0; i < std::atoi(argv[2]); ++i) {
    const auto start = std::chrono::steady_clock::now();
    auto reader = itk::ImageFileReader<Image>::New();
    reader->SetFileName(argv[1]);
    reader->Update();
    voxels = reader->GetOutput()->GetLargestPossibleRegion().GetNumberOfPixels();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(t.begin(), t.end());
  std::printf("{\"seconds\": %.9f, \"voxels\": %llu}\n", t[t.size() / 2], voxels);
  return 0;
}
