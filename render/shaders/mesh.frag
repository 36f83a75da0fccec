#version 450
// Two-sided Lambert with a headlight and a fill light; the back of a surface reads darker.
in vec3 worldNormal;
uniform vec3 viewDirection;  // from the camera into the scene
uniform vec3 colour;
out vec4 fragColour;
void main() {
  vec3 n = normalize(worldNormal);
  float facing = dot(n, -viewDirection);
  float light = 0.15 + 0.75 * max(facing, 0.0) + 0.15 * max(dot(n, normalize(vec3(0.3, 0.5, 0.8))), 0.0);
  vec3 c = facing >= 0.0 ? colour : colour * 0.35;
  fragColour = vec4(c * light, 1.0);
}
