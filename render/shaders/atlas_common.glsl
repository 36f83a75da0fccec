// What the atlas shaders share: the patch list (render/gpu_patches.h), the atlas textures, the
// camera, and the two rules that set a patch's tessellation levels. A patch's spacings count its
// own texels: the chart's, or on a tile with a detail chart, the detail chart's (detailRatio per
// chart texel); lengths on the screen are measured between chart texels everywhere.
layout(std430, binding = 0) readonly buffer Patches { uvec4 patches[]; };
layout(std430, binding = 1) readonly buffer DetailSlots { int detailSlots[]; };  // per chart; -1: none
layout(binding = 0) uniform sampler2D positions;  // RGB32F, world millimetres
layout(binding = 1) uniform sampler2D normals;    // RGB16_SNORM
layout(binding = 2) uniform sampler2D detailPositions;
layout(binding = 3) uniform sampler2D detailNormals;
uniform uint chartSize;     // N texels a side
uniform uint atlasColumns;  // chart slots per atlas row
uniform uint detailRatio;   // detail texels per chart texel (1 without detail charts)
uniform uint detailSize;    // M texels a side
uniform uint detailColumns;
uniform mat4 model;         // this instance's placement
uniform mat4 viewProjection;
uniform vec2 viewport;      // pixels
uniform float nearPlane;
uniform int gpuMode;        // 0: a fixed number of halvings per CPU edge; 1: segments of gpuPixels
uniform uint gpuLevel;
uniform float gpuPixels;
uniform uint maxTessLevel;  // a power of two the driver accepts

uint patchSide(uvec4 p) { return p.z & 0xffffu; }
ivec2 patchOrigin(uvec4 p) { return ivec2(p.y & 0xffffu, p.y >> 16); }

ivec2 atlasTexel(uint chart, ivec2 texel) {
  return ivec2((chart % atlasColumns) * chartSize, (chart / atlasColumns) * chartSize) + texel;
}
vec3 chartPosition(uint chart, ivec2 texel) { return texelFetch(positions, atlasTexel(chart, texel), 0).xyz; }
vec3 chartNormal(uint chart, ivec2 texel) { return texelFetch(normals, atlasTexel(chart, texel), 0).xyz; }
ivec2 detailTexel(int slot, ivec2 texel) {
  return ivec2((uint(slot) % detailColumns) * detailSize, (uint(slot) / detailColumns) * detailSize) + texel;
}
uint patchRatio(uvec4 p) { return detailSlots[p.x] >= 0 ? detailRatio : 1u; }

// Length in pixels between two texels of a chart. Symmetric in its arguments bit for bit, so the
// two charts of a tile side, which hold the same texels in opposite order, agree.
float screenLength(uint chart, ivec2 a, ivec2 b) {
  precise vec4 ca = viewProjection * (model * vec4(chartPosition(chart, a), 1.0));
  precise vec4 cb = viewProjection * (model * vec4(chartPosition(chart, b), 1.0));
  precise vec2 pa = ca.xy / max(ca.w, nearPlane) * viewport * 0.5;
  precise vec2 pb = cb.xy / max(cb.w, nearPlane) * viewport * 0.5;
  precise vec2 d = pa - pb;
  precise float l = sqrt(d.x * d.x + d.y * d.y);
  return l;
}

// The spacing (texels, a power of two) that `segments` segments or more give over `extent` texels.
uint spacingFor(uint extent, float segments) {
  uint wanted = uint(min(ceil(max(segments, 1.0)), 65536.0));
  uint pow2 = 1u << uint(findMSB(wanted) + (bitCount(wanted) > 1 ? 1 : 0));
  return max(1u, extent / pow2);
}

// Rule two: side k's spacing in the patch's texels, from its border class alone (see gpu_patches.h).
uint sideSpacing(uvec4 p, int k) {
  uint bits = (p.w >> (8 * k)) & 0xffu, r = patchRatio(p);
  uint cpu = (1u << (bits & 7u)) * r, extent = 1u << ((bits >> 3) & 7u);
  uint sigma;
  if (gpuMode == 0) {
    sigma = max(1u, cpu >> gpuLevel);
  } else {
    uint s = patchSide(p);
    ivec2 o = patchOrigin(p);
    bool row = k % 2 == 0;
    uint line = row ? (k == 0 ? o.y : o.y + s) : (k == 1 ? o.x + s : o.x);
    uint start = ((row ? o.x : o.y) / extent) * extent;
    ivec2 a = row ? ivec2(start, line) : ivec2(line, start);
    ivec2 step = row ? ivec2(1, 0) : ivec2(0, 1);
    ivec2 m = a + step * int(extent / 2u), b = a + step * int(extent);
    precise float length = screenLength(p.x, a, m) + screenLength(p.x, m, b);
    sigma = min(cpu, spacingFor(extent * r, length / gpuPixels));
  }
  sigma = max(sigma, max(1u, extent * r / maxTessLevel));
  return ((bits >> 6) & 1u) != 0u ? max(sigma, r) : sigma;  // a coarse border: chart texels only
}

// Rule one: the inner spacing in the patch's texels, from the patch alone (its CPU vertices, its
// size on the screen). A whole tile takes at most half its side, its centre as CPU level 1 has it: in
// one cell the driver would cut it along a diagonal of its choosing, and where a corner lies in only
// two tiles both tiles' other diagonals are one edge, so the two would fold over each other.
uint innerSpacing(uvec4 p) {
  uint s = patchSide(p), r = patchRatio(p), cpu = (1u << (p.z >> 24)) * r, sigma;
  if (gpuMode == 0) {
    sigma = max(1u, cpu >> gpuLevel);
  } else {
    ivec2 o = patchOrigin(p);
    ivec2 c00 = o, c10 = o + ivec2(s, 0), c01 = o + ivec2(0, s), c11 = o + ivec2(s, s);
    float length = max(max(screenLength(p.x, c00, c10), screenLength(p.x, c01, c11)),
                       max(screenLength(p.x, c00, c01), screenLength(p.x, c10, c11)));
    sigma = min(cpu, spacingFor(s * r, length / gpuPixels));
  }
  sigma = max(sigma, max(1u, s * r / maxTessLevel));
  return s == chartSize - 1u ? min(sigma, s * r / 2u) : sigma;
}
