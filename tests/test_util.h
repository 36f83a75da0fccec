// Helpers shared by the tests: a scratch folder per test, small synthetic volumes and meshes.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "core/mesh.h"
#include "core/volume.h"

namespace isoatlas::test {

// A fresh, empty folder named after the running test.
inline std::filesystem::path scratchDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  auto dir = std::filesystem::temp_directory_path() / "isoatlas-tests" /
             (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline void writeBytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}
inline std::string readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A golden file pins a format: `written` (what the writer makes of the golden's known contents) must
// equal the file byte for byte. ISOATLAS_WRITE_GOLDEN=1 writes the file instead: a format change is
// then a deliberate change of the committed file, with a version bump. A run that writes goldens
// fails (it compared nothing): run the tests again without it.
// `decode` turns both into what the format pins where its bytes are not the writer's alone (a
// compressed file: the bytes zlib's deflate makes differ between zlib versions).
inline void expectGolden(const std::filesystem::path& golden, const std::string& written,
                         std::string (*decode)(const std::string&) = nullptr) {
  if (std::getenv("ISOATLAS_WRITE_GOLDEN")) {
    writeBytes(golden, written);
    ADD_FAILURE() << "wrote " << golden << " (ISOATLAS_WRITE_GOLDEN): nothing was compared; run again without it";
    return;
  }
  const std::string committed = readBytes(golden);
  EXPECT_TRUE(decode ? decode(committed) == decode(written) : committed == written)
      << golden << " differs from what the writer makes of its contents";
}

// The Error that `work` throws, for the test to check its message and exit code. When it throws none,
// records a failure saying that `what` was accepted, and returns an Error with an empty message.
template <class F>
Error thrownError(F&& work, const std::string& what) {
  try {
    work();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << what << " was accepted";
  return Error("");
}

// A float volume whose voxel (x, y, z) holds f(x, y, z), unit spacing at the origin.
template <class F>
Volume fieldVolume(std::array<std::int64_t, 3> dims, F f) {
  Volume v = Volume::zeros(dims, ScalarType::Float32);
  for (std::int64_t z = 0; z < dims[2]; ++z)
    for (std::int64_t y = 0; y < dims[1]; ++y)
      for (std::int64_t x = 0; x < dims[0]; ++x) v.setValue(v.index(x, y, z), f(double(x), double(y), double(z)));
  return v;
}

// A volume of the given type whose voxel (i,j,k) holds a value that differs at every voxel
// (within the type's range), with a non-trivial spacing and origin.
inline Volume rampVolume(ScalarType type, std::array<std::int64_t, 3> dims = {7, 5, 4}) {
  Volume v = Volume::zeros(dims, type);
  v.spacing = {0.5, 1.25, 2.0};
  v.origin = {-10.5, 3.25, 7.0};
  for (std::size_t n = 0; n < v.voxelCount(); ++n)
    v.setValue(n, isFloating(type) ? double(n) * 0.37 - 4.0 : double(n % 100) + (type == ScalarType::Int8 ? -50 : 0));
  return v;
}

// A closed, consistently oriented octahedron (6 vertices, 8 triangles, genus 0).
inline Mesh octahedron() {
  Mesh m;
  m.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  m.addFace({0, 2, 4});
  m.addFace({2, 1, 4});
  m.addFace({1, 3, 4});
  m.addFace({3, 0, 4});
  m.addFace({2, 0, 5});
  m.addFace({1, 2, 5});
  m.addFace({3, 1, 5});
  m.addFace({0, 3, 5});
  return m;
}

// An n x m grid torus of quads (closed, genus 1) with radii R and r.
inline Mesh quadTorus(int n, int m, double R = 2, double r = 0.5) {
  Mesh t;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double a = 2 * M_PI * i / n, b = 2 * M_PI * j / m;
      t.positions.push_back({(R + r * std::cos(b)) * std::cos(a), (R + r * std::cos(b)) * std::sin(a), r * std::sin(b)});
    }
  auto id = [&](int i, int j) { return std::uint32_t(((i + n) % n) * m + (j + m) % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) t.addFace({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return t;
}

}  // namespace isoatlas::test
