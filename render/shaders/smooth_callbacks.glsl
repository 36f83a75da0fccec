// What OpenSubdiv's patch shaders ask of their user (the Osd* functions), and the displacement that
// puts the atlas's detail on the limit surface: the limit point P moved along the limit normal to
// the atlas's point of the same face (u, v), and the atlas's normal for shading.
uniform mat4 model;           // this instance's placement: "model view" is world here
uniform mat4 viewProjection;
uniform float tessLevel;
uniform int PrimitiveIdBase;
uniform int displace;
uniform uint chartSize;
uniform uint atlasColumns;
layout(binding = 0) uniform sampler2D positions;
layout(binding = 1) uniform sampler2D normals;

mat4 OsdModelViewMatrix() { return model; }
mat4 OsdProjectionMatrix() { return viewProjection; }
mat4 OsdModelViewProjectionMatrix() { return viewProjection * model; }
float OsdTessLevel() { return tessLevel; }
int OsdGregoryQuadOffsetBase() { return 0; }
int OsdPrimitiveIdBase() { return PrimitiveIdBase; }
int OsdBaseVertex() { return 0; }

// Face f's point (u, v) in the atlas, for bilinear filtering between its texels.
vec2 atlasCoordinate(int face, vec2 uv) {
  vec2 slot = vec2(float(uint(face) % atlasColumns), float(uint(face) / atlasColumns)) * float(chartSize);
  return (slot + clamp(uv, 0.0, 1.0) * float(chartSize - 1u) + 0.5) / vec2(textureSize(positions, 0));
}

// (Where the limit normal vanishes, at a degenerate patch corner, the point stays on the limit.)
#undef OSD_DISPLACEMENT_CALLBACK
#define OSD_DISPLACEMENT_CALLBACK                                                    \
  if (displace != 0 && dot(N, N) > 0.0) {                                            \
    vec2 at = atlasCoordinate(int(outpt.v.patchCoord.w), outpt.v.patchCoord.xy);     \
    vec3 n = normalize(N);                                                           \
    vec3 detailed = P + n * dot(texture(positions, at).xyz - P, n);                  \
    outpt.v.position = OsdModelViewMatrix() * vec4(detailed, 1.0);                   \
    outpt.v.normal = mat3(OsdModelViewMatrix()) * texture(normals, at).xyz;          \
  }
