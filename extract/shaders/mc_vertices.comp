#version 450
// Pass 2: one vertex per used grid edge, at edgeOffset[point] + its rank among the point's edges:
// the grid point and the crossing's parameter t along the axis (the CPU adds them in double), and
// (DRAWN_VERTICES) the vertex as a renderer draws it (position and outward normal, in floats), with
// the box of them all; a march only read back leaves them out (its gradients cost 12 field reads a vertex).
layout(local_size_x = 256) in;
#include "marching.glsl"
layout(std430, binding = 6) readonly buffer EdgeBits { uint edgeBits[]; };
layout(std430, binding = 8) readonly buffer EdgeOffset { uint edgeOffset[]; };
struct Vertex { ivec3 point; float t; int axis; int unused0; int unused1; int unused2; };
layout(std430, binding = 9) writeonly buffer Vertices { Vertex vertices[]; };
uniform uint pointCount;
#if DRAWN_VERTICES
struct DrawnVertex { vec4 position; vec4 normal; };
layout(std430, binding = 12) writeonly buffer DrawnVertices { DrawnVertex drawn[]; };
// The bits of (lowest + 1, highest + 1) per axis: never negative, so uint order is float order.
layout(std430, binding = 13) buffer Bounds { uint lowest[3]; uint highest[3]; };

shared uint groupLowest[3], groupHighest[3];
shared bool groupHasVertices;

// The field's gradient at grid point p, by central differences (one-sided differences would tilt
// the normals of a surface beside the grid's border, where sampleField mirrors).
vec3 gradientAt(ivec3 p) {
  return vec3(sampleField(p + ivec3(1, 0, 0)) - sampleField(p - ivec3(1, 0, 0)),
              sampleField(p + ivec3(0, 1, 0)) - sampleField(p - ivec3(0, 1, 0)),
              sampleField(p + ivec3(0, 0, 1)) - sampleField(p - ivec3(0, 0, 1)));
}
#endif

void main() {
#if DRAWN_VERTICES
  if (gl_LocalInvocationIndex == 0u) {
    for (int a = 0; a < 3; ++a) groupLowest[a] = 0xffffffffu, groupHighest[a] = 0u;
    groupHasVertices = false;
  }
  memoryBarrierShared();
  barrier();
#endif
  uint i = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * 256u) + gl_GlobalInvocationID.x;
  uint bits = i < pointCount ? edgeBits[i] : 0u;
  if (bits != 0u) {
    ivec3 p = pointAt(i);
    uint slot = edgeOffset[i];
    float a = sampleField(p);
#if DRAWN_VERTICES
    groupHasVertices = true;
    vec3 gradientP = gradientAt(p);
#endif
    for (int axis = 0; axis < 3; ++axis) {
      if ((bits & (1u << axis)) == 0u) continue;
      ivec3 q = p;
      q[axis] += 1;
      float b = sampleField(q);
      Vertex v;
      v.point = p;
      v.t = clamp((iso - a) / (b - a), 1e-3, 1.0 - 1e-3);
      v.axis = axis;
#if DRAWN_VERTICES
      vec3 position = vec3(p);
      position[axis] += v.t;
      // Inside is above iso: the outward normal runs down the gradient (down the edge where the
      // central differences cancel).
      vec3 g = mix(gradientP, gradientAt(q), v.t);
      if (length(g) == 0.0) g[axis] = b - a;
      drawn[slot] = DrawnVertex(vec4(position, 1.0), vec4(-normalize(g), 0.0));
      for (int k = 0; k < 3; ++k) {
        atomicMin(groupLowest[k], floatBitsToUint(position[k] + 1.0));
        atomicMax(groupHighest[k], floatBitsToUint(position[k] + 1.0));
      }
#endif
      vertices[slot++] = v;
    }
  }
#if DRAWN_VERTICES
  memoryBarrierShared();
  barrier();
  if (gl_LocalInvocationIndex == 0u && groupHasVertices) {
    for (int k = 0; k < 3; ++k) {
      atomicMin(lowest[k], groupLowest[k]);
      atomicMax(highest[k], groupHighest[k]);
    }
  }
#endif
}
