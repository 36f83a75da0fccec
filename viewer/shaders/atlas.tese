#version 450
// Every vertex the tessellator makes lands on a texel of the chart (the levels divide the patch's
// side), so it is read, not interpolated: the same bits on both charts of a tile side.
#include "atlas_common.glsl"
layout(quads, equal_spacing, ccw) in;
patch in uvec4 tessPatch;
out vec3 tessWorld;
out vec3 tessNormal;
out vec2 tessTexel;  // in the chart, texels
flat out uint tessChart;
void main() {
  uvec4 p = tessPatch;
  ivec2 texel = patchOrigin(p) + ivec2(round(gl_TessCoord.xy * float(patchSide(p))));
  tessWorld = (model * vec4(chartPosition(p.x, texel), 1.0)).xyz;
  tessNormal = mat3(model) * chartNormal(p.x, texel);
  tessTexel = vec2(texel);
  tessChart = p.x;
  gl_Position = viewProjection * vec4(tessWorld, 1.0);
}
