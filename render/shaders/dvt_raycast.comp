#version 450
// Ray casting of a DVT, one thread per pixel (a fragment stage left seams on llvmpipe, where quads were
// split by the viewport's two triangles). The surface is the zero set of the inside-ness field (leaf
// value times its radius, world units) interpolated between the leaves, as a level set's is between
// voxels: the walk goes from leaf to leaf along the ray, skipping coarse leaves outside the band whole,
// samples the field a lattice cell apart through the others, and finds its first sign change by
// bisection; the normal is the field's gradient there (central differences). (Stopping at the first leaf whose centre is
// inside placed the surface on the leaves' boxes: voxel-sized terraces.)
#include "dvt_tree.glsl"
#include "shading.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba8, binding = 0) uniform writeonly image2D target;
uniform mat4 inverseViewProjection, worldToIndex;
uniform vec3 background;
uniform float radius[MAX_DEPTH + 1];
uniform vec2 viewportSize;

// The inside-ness of leaf `node` (world units), within +-band: a coarse uniform leaf says only "at
// least its radius", which would read as a steep slope beside a fine one.
float field(uint node, float band) {
  return clamp(pointers[node].value * radius[depthOf(cells[node])], -band, band);
}

// The field interpolated trilinearly between the centres of a lattice of cells of size `cell` (index
// units) around p, as a volume's texture is: the leaves' values alone are piecewise constant.
float smoothField(vec3 p, vec3 cell, float band) {
  vec3 u = (p + 0.5) / cell - 0.5, base = floor(u), f = u - base;
  uint nodes[8];
  cornerLeaves((base + 0.5) * cell - 0.5, (base + 1.0 + 0.5) * cell - 0.5, nodes);
  float v[8];
  for (int i = 0; i < 8; ++i) v[i] = field(nodes[i], band);
  vec4 x = vec4(mix(v[0], v[1], f.x), mix(v[2], v[3], f.x), mix(v[4], v[5], f.x), mix(v[6], v[7], f.x));
  vec2 y = vec2(mix(x[0], x[1], f.y), mix(x[2], x[3], f.y));
  return mix(y[0], y[1], f.z);
}

// Its gradient by central differences a cell apart: continuous across the lattice's faces, where the
// trilinear field's own gradient jumps and would light every cell apart.
vec3 smoothGradient(vec3 p, vec3 cell, float band) {
  vec3 g;
  for (int a = 0; a < 3; ++a) {
    vec3 e = vec3(0.0);
    e[a] = 0.5 * cell[a];
    g[a] = (smoothField(p + e, cell, band) - smoothField(p - e, cell, band)) / cell[a];
  }
  return g;
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
  float tStart = max(max(max(tmin.x, tmin.y), tmin.z), 0.0), tEnd = min(min(tmax.x, tmax.y), min(tmax.z, 1.0));
  // The walk brackets the first sign change: the last sample at or below zero (a, va) and the first
  // above it (b, vb). A sampled stretch begins half a step before its leaf, where a crossing the last
  // skipped leaf holds at its far face is caught.
  bool found = false, sampling = false;
  float t = tStart, a = tStart, va = 0.0, b = tStart, vb = 0.0, band = 1.0;
  vec3 cell = vec3(1.0);
  for (int step = 0; step < 262144 && !found && t < tEnd; ++step) {
    Leaf l = leafToward(o + t * d, d);
    vec3 exits = max((l.lo - o) * inv, (l.lo + l.size - o) * inv);
    float tExit = min(min(min(exits.x, exits.y), exits.z), tEnd);
    bool fine = all(lessThanEqual(l.size, vec3(1.0)));
    if (fine || pointers[l.node].value > -1.0) {
      if (!sampling) {
        cell = min(l.size, vec3(1.0));
        band = 2.0 * radius[depthOf(cells[l.node])];
        a = max(t - 0.5 * min(min(cell.x, cell.y), cell.z) / length(d), tStart);
        va = smoothField(o + a * d, cell, band);
        found = va > 0.0;  // the ray starts inside
        b = a;
        sampling = true;
      }
      float h = min(min(cell.x, cell.y), cell.z) / length(d);
      float s = max(t, a + h);
      for (int i = 0; i < 65536 && !found && s < tExit + h; ++i, s += h) {
        b = min(s, tExit);
        vb = smoothField(o + b * d, cell, band);
        found = vb > 0.0;
        if (!found) a = b, va = vb;
      }
    } else {
      sampling = false;
    }
    if (!found) t = max(tExit, t) + 1e-4 * min(min(l.size.x, l.size.y), l.size.z) / length(d);
  }
  if (!found) {
    imageStore(target, pixel, vec4(background, 1.0));
    return;
  }
  float hit = a;
  if (va <= 0.0) {
    for (int i = 0; i < 5; ++i) {
      float m = 0.5 * (a + b), vm = smoothField(o + m * d, cell, band);
      if (vm > 0.0) b = m, vb = vm;
      else a = m, va = vm;
    }
    hit = a + (b - a) * va / (va - vb);
  }
  vec3 g = smoothGradient(o + hit * d, cell, band);
  vec3 world = (indexToWorld * vec4(o + hit * d, 1.0)).xyz;
  vec3 normal = length(g) > 0.0 ? normalToWorld * -g : normalToWorld * -d;
  if (dot(normal, eye - world) < 0.0) normal = -normal;  // a first hit faces the eye
  imageStore(target, pixel, vec4(shade(world, normal, 0u), 1.0));
}
