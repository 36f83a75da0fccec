#include "pipeline/mask_topology.h"

#include <array>
#include <vector>

#include "core/mesh_topology.h"
#include "extract/marching_cubes.h"

namespace isoatlas::pipeline {

namespace {

// The 6-connected components of {inside > 0}, by flood fill.
std::int64_t componentsOf(const std::vector<float>& inside, const std::array<std::int64_t, 3>& d) {
  std::vector<std::uint8_t> seen(inside.size(), 0);
  std::vector<std::int64_t> stack;
  std::int64_t components = 0;
  const std::int64_t step[3] = {1, d[0], d[0] * d[1]};
  for (std::int64_t start = 0; start < std::int64_t(inside.size()); ++start) {
    if (inside[std::size_t(start)] == 0 || seen[std::size_t(start)]) continue;
    ++components;
    seen[std::size_t(start)] = 1;
    stack.push_back(start);
    while (!stack.empty()) {
      const std::int64_t n = stack.back();
      stack.pop_back();
      const std::int64_t at[3] = {n % d[0], n / d[0] % d[1], n / (d[0] * d[1])};
      for (int a = 0; a < 3; ++a)
        for (const int s : {-1, 1}) {
          if (at[a] + s < 0 || at[a] + s >= d[a]) continue;
          const std::int64_t m = n + s * step[a];
          if (inside[std::size_t(m)] == 0 || seen[std::size_t(m)]) continue;
          seen[std::size_t(m)] = 1;
          stack.push_back(m);
        }
    }
  }
  return components;
}

}  // namespace

MaskTopology maskTopology(const Volume& mask) {
  std::vector<float> inside(mask.voxelCount());
  for (std::size_t n = 0; n < inside.size(); ++n) inside[n] = mask.value(n) > 0 ? 1.0f : 0.0f;
  const extract::Grid grid{.dims = mask.dims, .values = inside.data()};
  const MeshTopology t = analyzeTopology(extract::marchingCubes(levelset::Backend::Cpu, grid, 0.5f).mesh);
  return {componentsOf(inside, mask.dims), std::int64_t(t.components), std::int64_t(t.euler)};
}

}  // namespace isoatlas::pipeline
