// gpuPatches: the adaptive mesh's patches (multires::Patch: a square of a chart, (u, v, s, c)) as the
// tessellation shaders read them, with what each needs to refine its border so that neighbours agree.
//
// The GPU refines a patch side into segments of sigma texels (a power of two), so every vertex it
// makes is a texel of the chart and the texels of a tile side are the same bits in both charts
// (atlas/make_atlas): equal segment lengths on both sides of a border mean equal vertices. Patch
// sides meet at T-junctions (a side of length 2s across two of length s), so a side's sigma must not
// depend on the side alone: each side belongs to a border class, the sides on the same chart line
// (or the same base edge, across two charts) that overlap; since patches are dyadic squares, a class
// is its longest side (the class extent) with the sides it holds. Per side this keeps:
//   cpu spacing: the largest power of two, at most the class's shortest side, that has every CPU
//                vertex on the extent on its multiples (so the GPU never drops a CPU vertex)
//   extent:      the class extent's length; the shader finds the extent from its own side (the
//                extent is aligned to its length) and measures its length on the screen
// The shader takes sigma = min(cpu spacing, what the view asks of the extent), at least one texel
// and at least extent / 64, and sets the side's outer level to side / sigma: the paper's second rule,
// outer levels only from what lies on the border. The inner level comes from the patch alone: its
// own cpu spacing (half the side when the patch holds an odd-level vertex, c > 0, and at most half
// for a whole tile: see atlas_common.glsl) and its own size on the screen: the paper's first rule.
// Tiles with a detail chart (edit-detail) refine on to its texels, r = (M - 1) / (N - 1) per chart
// texel: the shader counts their spacings in detail texels, r times the above. A side on a tile
// border whose other tile has no detail chart is marked coarse: there sigma stays at least r (one
// chart texel) and the vertices are read from the chart, as the tile across reads them.
//
// Inputs: the adaptive mesh; per tile and side the tile and side across (atlas::sidesAcross); per
// tile whether it has a detail chart (empty: none has).
// Output: one GpuPatch per patch, in mesh.patches() order.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "atlas/tile_sides.h"
#include "multires/adaptive_mesh.h"

namespace isoatlas::render {

// 16 bytes, the layout of the shaders' uvec4 (render/shaders/atlas_patch.glsl).
struct GpuPatch {
  std::uint32_t chart;
  std::uint32_t origin;  // u | v << 16, texels
  std::uint32_t size;    // s | c << 16 | log2(inner cpu spacing) << 24
  std::uint32_t sides;   // byte k for side k (0 v = v0, 1 u = u0 + s, 2 v = v0 + s, 3 u = u0):
                         // log2(cpu spacing) | log2(extent) << 3 | coarse << 6
  bool operator==(const GpuPatch&) const = default;
};

std::vector<GpuPatch> gpuPatches(const multires::AdaptiveMesh& mesh,
                                 const std::vector<std::array<atlas::SideAcross, 4>>& across,
                                 const std::vector<bool>& hasDetail = {});


}  // namespace isoatlas::render
