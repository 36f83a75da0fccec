#version 450
// Every vertex the tessellator makes lands on a texel of the chart (the levels divide the patch's
// side), so it is read, not interpolated: the same bits on both charts of a tile side. On a tile
// with a detail chart, its texels; the chart's on a coarse border and at the tile's corners, where
// tiles without one meet it.
#include "atlas_common.glsl"
layout(quads, equal_spacing, ccw) in;
patch in uvec4 tessPatch;
out vec3 tessWorld;
out vec3 tessNormal;
out vec2 tessTexel;  // in the chart, chart texels
flat out uint tessChart;
bool onCoarseBorder(uvec4 p, vec2 t) {
  bool side[4] = bool[4](t.y == 0.0, t.x == 1.0, t.y == 1.0, t.x == 0.0);
  for (int k = 0; k < 4; ++k)
    if (side[k] && ((p.w >> (8 * k + 6)) & 1u) != 0u) return true;
  return false;
}

void main() {
  uvec4 p = tessPatch;
  int slot = detailSlots[p.x];
  uint r = patchRatio(p), last = (chartSize - 1u) * r;
  ivec2 texel = patchOrigin(p) * int(r) + ivec2(round(gl_TessCoord.xy * float(patchSide(p) * r)));
  bool corner = (texel.x == 0 || texel.x == int(last)) && (texel.y == 0 || texel.y == int(last));
  vec3 position, normal;
  if (slot < 0 || corner || onCoarseBorder(p, gl_TessCoord.xy)) {
    position = chartPosition(p.x, texel / int(r));
    normal = chartNormal(p.x, texel / int(r));
  } else {
    position = texelFetch(detailPositions, detailTexel(slot, texel), 0).xyz;
    normal = texelFetch(detailNormals, detailTexel(slot, texel), 0).xyz;
  }
  tessWorld = (model * vec4(position, 1.0)).xyz;
  tessNormal = mat3(model) * normal;
  tessTexel = vec2(texel) / float(r);
  tessChart = p.x;
  gl_Position = viewProjection * vec4(tessWorld, 1.0);
}
