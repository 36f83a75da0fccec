// The GLSL twin of levelset/speed.h: evaluateVoxel and timeStep, line for line. Its constants come
// from speed.h as defines (CLAMP, CFL_FRACTION, RESCALE_SPEED, CURVATURE_LIMIT), so the two cannot
// drift apart.
const float kClamp = CLAMP;

struct VoxelUpdate { float speed; float rate; };

float sq(float v) { return v * v; }

float at(float u[27], int dx, int dy, int dz) { return u[(dz + 1) * 9 + (dy + 1) * 3 + (dx + 1)]; }

float faceNormal(float along, float a, float b) {
  float len = sqrt(along * along + a * a + b * b);
  return len > 0.0 ? along / len : 0.0;
}

float upwindGradient(float speed, float dxp, float dxm, float dyp, float dym, float dzp, float dzm) {
  float sumMax = sq(max(dxp, 0.0)) + sq(max(-dxm, 0.0)) + sq(max(dyp, 0.0)) +
                 sq(max(-dym, 0.0)) + sq(max(dzp, 0.0)) + sq(max(-dzm, 0.0));
  float sumMin = sq(min(dxp, 0.0)) + sq(min(-dxm, 0.0)) + sq(min(dyp, 0.0)) +
                 sq(min(-dym, 0.0)) + sq(min(dzp, 0.0)) + sq(min(-dzm, 0.0));
  return sqrt(speed > 0.0 ? sumMax : sumMin);
}

VoxelUpdate evaluateVoxel(float u[27], float intensity, float target, float width, float alpha) {
  float c = at(u, 0, 0, 0);
  float dxp = at(u, 1, 0, 0) - c, dxm = c - at(u, -1, 0, 0);
  float dyp = at(u, 0, 1, 0) - c, dym = c - at(u, 0, -1, 0);
  float dzp = at(u, 0, 0, 1) - c, dzm = c - at(u, 0, 0, -1);
  float dx = 0.5 * (at(u, 1, 0, 0) - at(u, -1, 0, 0));
  float dy = 0.5 * (at(u, 0, 1, 0) - at(u, 0, -1, 0));
  float dz = 0.5 * (at(u, 0, 0, 1) - at(u, 0, 0, -1));
  float dyAtXp = 0.5 * (at(u, 1, 1, 0) - at(u, 1, -1, 0)), dyAtXm = 0.5 * (at(u, -1, 1, 0) - at(u, -1, -1, 0));
  float dzAtXp = 0.5 * (at(u, 1, 0, 1) - at(u, 1, 0, -1)), dzAtXm = 0.5 * (at(u, -1, 0, 1) - at(u, -1, 0, -1));
  float dxAtYp = 0.5 * (at(u, 1, 1, 0) - at(u, -1, 1, 0)), dxAtYm = 0.5 * (at(u, 1, -1, 0) - at(u, -1, -1, 0));
  float dzAtYp = 0.5 * (at(u, 0, 1, 1) - at(u, 0, 1, -1)), dzAtYm = 0.5 * (at(u, 0, -1, 1) - at(u, 0, -1, -1));
  float dxAtZp = 0.5 * (at(u, 1, 0, 1) - at(u, -1, 0, 1)), dxAtZm = 0.5 * (at(u, 1, 0, -1) - at(u, -1, 0, -1));
  float dyAtZp = 0.5 * (at(u, 0, 1, 1) - at(u, 0, -1, 1)), dyAtZm = 0.5 * (at(u, 0, 1, -1) - at(u, 0, -1, -1));
  float nxp = faceNormal(dxp, 0.5 * (dyAtXp + dy), 0.5 * (dzAtXp + dz));
  float nxm = faceNormal(dxm, 0.5 * (dyAtXm + dy), 0.5 * (dzAtXm + dz));
  float nyp = faceNormal(dyp, 0.5 * (dxAtYp + dx), 0.5 * (dzAtYp + dz));
  float nym = faceNormal(dym, 0.5 * (dxAtYm + dx), 0.5 * (dzAtYm + dz));
  float nzp = faceNormal(dzp, 0.5 * (dxAtZp + dx), 0.5 * (dyAtZp + dy));
  float nzm = faceNormal(dzm, 0.5 * (dxAtZm + dx), 0.5 * (dyAtZm + dy));
  float curvature = 0.5 * ((nxp - nxm) + (nyp - nym) + (nzp - nzm));

  float data = width - abs(intensity - target);
  float rescale = (c / kClamp) * (1.0 - sqrt(dx * dx + dy * dy + dz * dz));
  float physical = alpha * data + (1.0 - alpha) * curvature;
  float speed = physical + rescale;

  VoxelUpdate r;
  r.speed = physical;
  r.rate = speed * upwindGradient(speed, dxp, dxm, dyp, dym, dzp, dzm);
  return r;
}

float timeStep(float maxSpeed, float alpha) {
  float dt = CFL_FRACTION / (maxSpeed + RESCALE_SPEED);
  if (alpha < 1.0) dt = min(dt, CURVATURE_LIMIT / (1.0 - alpha));
  return dt;
}
