#version 450
// Ray casting of a DVT, one thread per pixel (a fragment stage left seams on llvmpipe, where quads were
// split by the viewport's two triangles): from leaf to leaf along the ray (empty leaves skipped whole) to the first leaf
// whose centre is inside; the surface is placed and lit from the inside-ness field (leaf value times
// its radius, world units), interpolated between the leaves around the hit, and its gradient.
#include "dvt_tree.glsl"
#include "shading.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba8, binding = 0) uniform writeonly image2D target;
uniform mat4 inverseViewProjection, worldToIndex;
uniform vec3 background;
uniform float radius[MAX_DEPTH + 1];
uniform vec2 viewportSize;

// The inside-ness at p (world units), within +-band: a coarse uniform leaf says only "at least its
// radius", which would read as a steep slope beside a fine one.
float field(vec3 p, float band) {
  Leaf l = leafAt(p);
  return clamp(pointers[l.node].value * radius[depthOf(cells[l.node])], -band, band);
}

// The field interpolated trilinearly between the centres of a lattice of cells of size `cell` (index
// units) around p, as a volume's texture is, and its gradient: the leaves' values alone are piecewise
// constant and would light cell-sized terraces.
float smoothField(vec3 p, vec3 cell, float band, out vec3 gradient) {
  vec3 u = (p + 0.5) / cell - 0.5, base = floor(u), f = u - base;
  float v[8];
  for (int i = 0; i < 8; ++i) v[i] = field((base + vec3(i & 1, (i >> 1) & 1, i >> 2) + 0.5) * cell - 0.5, band);
  vec4 x = vec4(mix(v[0], v[1], f.x), mix(v[2], v[3], f.x), mix(v[4], v[5], f.x), mix(v[6], v[7], f.x));
  vec4 dx = vec4(v[1] - v[0], v[3] - v[2], v[5] - v[4], v[7] - v[6]);
  vec2 y = vec2(mix(x[0], x[1], f.y), mix(x[2], x[3], f.y));
  gradient = vec3(mix(mix(dx[0], dx[1], f.y), mix(dx[2], dx[3], f.y), f.z), mix(x[1] - x[0], x[3] - x[2], f.z), y[1] - y[0]) / cell;
  return mix(y[0], y[1], f.z);
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= int(viewportSize.x) || pixel.y >= int(viewportSize.y)) return;
  vec2 ndc = 2.0 * (vec2(pixel) + 0.5) / viewportSize - 1.0;
  vec4 nearWorld = inverseViewProjection * vec4(ndc, -1.0, 1.0), farWorld = inverseViewProjection * vec4(ndc, 1.0, 1.0);
  vec3 o = (worldToIndex * vec4(nearWorld.xyz / nearWorld.w, 1.0)).xyz;
  vec3 d = (worldToIndex * vec4(farWorld.xyz / farWorld.w, 1.0)).xyz - o;  // t in [0, 1]: near to far
  d = mix(d, vec3(1e-20), equal(d, vec3(0.0)));  // no infinities times zero in the slab tests
  vec3 inv = 1.0 / d;
  float side = exp2(float(voxelSplits));
  vec3 ta = (vec3(-0.5) - o) * inv, tb = (vec3(side - 0.5) - o) * inv;
  vec3 tmin = min(ta, tb), tmax = max(ta, tb);
  float t = max(max(max(tmin.x, tmin.y), tmin.z), 0.0), tEnd = min(min(tmax.x, tmax.y), min(tmax.z, 1.0));
  // The walk finds the hit; the shading comes after it.
  bool found = false;
  float lastSpan = 0.0, span = 0.0;
  Leaf l;
  for (int step = 0; step < 262144 && !found && t < tEnd; ++step) {
    l = leafToward(o + t * d, d);
    vec3 exits = max((l.lo - o) * inv, (l.lo + l.size - o) * inv);
    float tExit = min(min(exits.x, exits.y), exits.z);
    found = pointers[l.node].value > 0.0;
    lastSpan = span;
    span = tExit - t;
    if (!found) t = max(tExit, t) + 1e-4 * min(min(l.size.x, l.size.y), l.size.z) / length(d);
  }
  if (!found) {
    imageStore(target, pixel, vec4(background, 1.0));
    return;
  }
  // The inside-ness field, smooth around the hit: where along the ray it crosses zero; the normal from
  // its gradient there. A lattice of the hit leaf's size, a voxel at most (coarser leaves are uniform).
  vec3 cell = min(l.size, vec3(1.0)), g;
  float band = 2.0 * radius[depthOf(cells[l.node])];
  vec3 p = o + t * d;
  float value = smoothField(p, cell, band, g), rate = dot(g, d);
  float hit = rate > 0.0 ? clamp(t - value / rate, t - lastSpan, t + span) : t;
  smoothField(o + hit * d, cell, band, g);
  vec3 world = (indexToWorld * vec4(o + hit * d, 1.0)).xyz;
  vec3 normal = length(g) > 0.0 ? normalToWorld * -g : normalToWorld * -d;
  if (dot(normal, eye - world) < 0.0) normal = -normal;  // a first hit faces the eye
  imageStore(target, pixel, vec4(shade(world, normal, 0u), 1.0));
}
