#version 450
// Ray casting of a scan and of a level set read straight from its pages (paged_phi.glsl: no dense
// phi), one thread per pixel, front to back in index space, half a voxel a step:
//   the scan through a transfer function (the window's ramp: grey, opacity rising with the square of
//   the windowed value), everywhere or only where phi > 0 (the level set as a region of interest);
//   the level set's zero set as a lit surface, placed between two samples by phi's interpolation and
//   lit from its gradient (trilinear phi, as the slices' contour);
//   a clipping plane: its positive side is cut away, and where a ray enters the kept side through the
//   plane the cut face is opaque, showing the scan with the level set's inside tinted and its contour.
#include "levelset/shaders/paged_phi.glsl"
#include "shading.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba8, binding = 1) uniform writeonly image2D target;
layout(binding = 0) uniform sampler3D source;
uniform mat4 inverseViewProjection, worldToIndex, indexToWorld;
uniform mat3 normalToWorld;
uniform ivec3 dims;
uniform vec2 viewportSize;
uniform vec3 background;
uniform vec2 window;  // intensities drawn black and white
uniform float opacity;  // per voxel of path, at white
uniform int showScan, insideOnly, showSurface, clipOn;
uniform vec4 clipPlane;  // index space: dot(xyz, p) + w > 0 is cut away

float phiAtVoxel(ivec3 c) {
  return any(lessThan(c, ivec3(0))) || any(greaterThanEqual(c, dims)) ? -PHI_CLAMP : pagedPhi(c);
}

// Trilinear between voxel centres; outside the volume reads as outside.
float phiAt(vec3 p) {
  ivec3 i = ivec3(floor(p));
  vec3 f = p - vec3(i);
  float c00 = mix(phiAtVoxel(i), phiAtVoxel(i + ivec3(1, 0, 0)), f.x);
  float c10 = mix(phiAtVoxel(i + ivec3(0, 1, 0)), phiAtVoxel(i + ivec3(1, 1, 0)), f.x);
  float c01 = mix(phiAtVoxel(i + ivec3(0, 0, 1)), phiAtVoxel(i + ivec3(1, 0, 1)), f.x);
  float c11 = mix(phiAtVoxel(i + ivec3(0, 1, 1)), phiAtVoxel(i + ivec3(1, 1, 1)), f.x);
  return mix(mix(c00, c10, f.y), mix(c01, c11, f.y), f.z);
}

float windowed(vec3 p) {
  float s = texture(source, (p + 0.5) / vec3(dims)).r;
  return clamp((s - window.x) / max(window.y - window.x, 1e-20), 0.0, 1.0);
}

vec3 gradientAt(vec3 p) {
  return vec3(phiAt(p + vec3(1, 0, 0)) - phiAt(p - vec3(1, 0, 0)), phiAt(p + vec3(0, 1, 0)) - phiAt(p - vec3(0, 1, 0)),
              phiAt(p + vec3(0, 0, 1)) - phiAt(p - vec3(0, 0, 1)));
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= int(viewportSize.x) || pixel.y >= int(viewportSize.y)) return;
  vec2 ndc = 2.0 * (vec2(pixel) + 0.5) / viewportSize - 1.0;
  vec4 nearWorld = inverseViewProjection * vec4(ndc, -1.0, 1.0), farWorld = inverseViewProjection * vec4(ndc, 1.0, 1.0);
  vec3 o = (worldToIndex * vec4(nearWorld.xyz / nearWorld.w, 1.0)).xyz;
  vec3 d = (worldToIndex * vec4(farWorld.xyz / farWorld.w, 1.0)).xyz - o;  // t in [0, 1]: near to far
  d = mix(d, vec3(1e-20), equal(d, vec3(0.0)));
  vec3 ta = (vec3(-0.5) - o) / d, tb = (vec3(dims) - 0.5 - o) / d;
  vec3 tmin = min(ta, tb), tmax = max(ta, tb);
  float t0 = max(max(max(tmin.x, tmin.y), tmin.z), 0.0), t1 = min(min(tmax.x, tmax.y), min(tmax.z, 1.0));
  bool face = false;
  if (clipOn != 0) {
    float s0 = dot(clipPlane.xyz, o) + clipPlane.w, rate = dot(clipPlane.xyz, d);
    if (rate == 0.0) {
      if (s0 > 0.0) t1 = -1.0;
    } else {
      float tp = -s0 / rate;
      if (rate > 0.0) t1 = min(t1, tp);
      else if (tp > t0) t0 = tp, face = true;
    }
  }
  vec3 colourSum = vec3(0.0);
  float alpha = 0.0;
  if (t0 < t1 && face) {  // the cut face
    vec3 p = o + t0 * d;
    float phi = phiAt(p), v = windowed(p);
    vec3 c = vec3(v);
    if (phi > 0.0) c = mix(c, colour, 0.35);
    if (abs(phi) < 0.35) c = vec3(1.0, 0.88, 0.0);
    imageStore(target, pixel, vec4(c, 1.0));
    return;
  }
  float dt = 0.5 / length(d);
  float previous = phiAt(o + t0 * d);
  for (float t = t0; t < t1 && alpha < 0.98; t += dt) {
    vec3 p = o + t * d;
    float phi = phiAt(p);
    if (showSurface != 0 && previous <= 0.0 && phi > 0.0) {
      float hit = t - dt * phi / (phi - previous);
      vec3 q = o + hit * d;
      vec3 world = (indexToWorld * vec4(q, 1.0)).xyz;
      vec3 g = gradientAt(q);
      vec3 normal = length(g) > 0.0 ? normalToWorld * -g : normalToWorld * -d;
      colourSum += (1.0 - alpha) * shade(world, normal, 0u);
      alpha = 1.0;
      break;
    }
    if (showScan != 0 && (insideOnly == 0 || phi > 0.0)) {
      float v = windowed(p);
      float a = 1.0 - pow(max(1.0 - opacity * v * v, 0.0), 0.5);  // half a voxel of path
      colourSum += (1.0 - alpha) * a * vec3(v);
      alpha += (1.0 - alpha) * a;
    }
    previous = phi;
  }
  imageStore(target, pixel, vec4(colourSum + (1.0 - alpha) * background, 1.0));
}
