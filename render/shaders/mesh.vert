#version 450
// A lit triangle mesh: one matrix takes positions to the screen (the world's view-projection times
// the mesh's own map to the world), another its normals to the world.
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 viewProjection;
uniform mat3 normalToWorld;
out vec3 worldNormal;
void main() {
  worldNormal = normalToWorld * normal;
  gl_Position = viewProjection * vec4(position, 1.0);
}
