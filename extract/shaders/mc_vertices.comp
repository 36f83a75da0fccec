#version 450
// Pass 2: one vertex per used grid edge, at edgeOffset[point] + its rank among the point's edges:
// the grid point and the crossing's parameter t along the axis (the CPU adds them in double).
layout(local_size_x = 256) in;
#include "marching.glsl"
layout(std430, binding = 6) readonly buffer EdgeBits { uint edgeBits[]; };
layout(std430, binding = 8) readonly buffer EdgeOffset { uint edgeOffset[]; };
struct Vertex { ivec3 point; float t; int axis; int unused0; int unused1; int unused2; };
layout(std430, binding = 9) writeonly buffer Vertices { Vertex vertices[]; };
uniform uint pointCount;

void main() {
  uint i = gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * 256u) + gl_GlobalInvocationID.x;
  if (i >= pointCount) return;
  uint bits = edgeBits[i];
  if (bits == 0u) return;
  ivec3 p = pointAt(i);
  uint slot = edgeOffset[i];
  float a = sampleField(p);
  for (int axis = 0; axis < 3; ++axis) {
    if ((bits & (1u << axis)) == 0u) continue;
    ivec3 q = p;
    q[axis] += 1;
    float b = sampleField(q);
    Vertex v;
    v.point = p;
    v.t = clamp((iso - a) / (b - a), 1e-3, 1.0 - 1e-3);
    v.axis = axis;
    vertices[slot++] = v;
  }
}
