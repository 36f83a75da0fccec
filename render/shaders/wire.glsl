// The wireframe's geometry-stage part, for both renderers: the height in pixels of each corner of
// the triangle over the opposite edge (a fragment's distance to edge i, interpolated noperspective,
// is 0 on it), and whether two points of a chart's unit square lie on one of its sides.
uniform vec2 viewport;

vec3 cornerHeights() {
  vec2 s[3];
  for (int i = 0; i < 3; ++i) s[i] = gl_in[i].gl_Position.xy / max(gl_in[i].gl_Position.w, 1e-6) * viewport * 0.5;
  float twiceArea = abs((s[1].x - s[0].x) * (s[2].y - s[0].y) - (s[2].x - s[0].x) * (s[1].y - s[0].y));
  vec3 h;
  for (int i = 0; i < 3; ++i) h[i] = twiceArea / max(length(s[(i + 2) % 3] - s[(i + 1) % 3]), 1e-6);
  return h;
}

bool onOneSide(vec2 a, vec2 b, float last) {
  return (a.x == 0.0 && b.x == 0.0) || (a.x == last && b.x == last) || (a.y == 0.0 && b.y == 0.0) || (a.y == last && b.y == last);
}
