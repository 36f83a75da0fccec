#version 450
// A lit triangle mesh: positions and normals in world space, one view-projection matrix.
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 viewProjection;
out vec3 worldNormal;
void main() {
  worldNormal = normal;
  gl_Position = viewProjection * vec4(position, 1.0);
}
