// Two-sided Lambert with a headlight (as mesh.frag), coloured by one colour or by chart.
uniform vec3 eye;
uniform vec3 colour;
uniform int colourByChart;

vec3 chartColour(uint c) {
  uint h = c * 2654435761u;
  return vec3(float((h >> 8) & 255u), float((h >> 16) & 255u), float((h >> 24) & 255u)) / 255.0 * 0.6 + 0.35;
}

vec3 shade(vec3 position, vec3 normal, uint chart) {
  vec3 n = normalize(normal);
  float facing = dot(n, normalize(eye - position));
  float light = 0.15 + 0.75 * abs(facing) + 0.15 * max(dot(n, normalize(vec3(0.3, 0.5, 0.8))), 0.0);
  vec3 c = colourByChart != 0 ? chartColour(chart) : colour;
  return (facing < 0.0 ? c * 0.35 : c) * light;
}
