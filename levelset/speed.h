// The level-set PDE of Lefohn's thesis (sec. 4.2.1, app. A), per voxel, in voxel units:
//   phi_t = F |grad phi|,  F = alpha D(I) + (1 - alpha) H + G_r,  D(I) = eps - |I - T|
//   H    = mean curvature by difference of normals, (1/2) div(grad phi / |grad phi|)
//   G_r  = (phi / kClamp) (1 - |grad phi|), the rescaling term that keeps phi a distance transform
//          clamped to [-kClamp, kClamp], so phi is flat (zero gradient) away from the front. phi is
//          divided by the clamp as in the thesis, which stores phi normalised to [0, 1].
//   |grad phi| upwind: from the one-sided differences, chosen by the sign of F (app. A.9-A.11).
// Sign convention, everywhere: phi > 0 inside the model, < 0 outside; F > 0 grows the model.
// I, T and eps are in the source volume's own intensity units (as ITK's threshold level set), so
// alpha weighs intensity units against 1/voxel. The GLSL twin is levelset/shaders/speed.glsl.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace isoatlas::levelset {

constexpr float kClamp = 3.0f;  // |phi| <= 3 voxels: a band of 6 voxels around the front (speed.glsl: CLAMP)

struct SpeedParams {
  float target = 0;  // T
  float width = 1;   // eps > 0
  float alpha = 0.5; // in [0, 1]: 1 pure intensity propagation, 0 pure curvature flow
};

// Activation message bits, one byte per active page (thesis sec. 3.3.5, app. C).
enum MessageBit : std::uint8_t {
  kNeedPlusX = 1, kNeedMinusX = 2, kNeedPlusY = 4, kNeedMinusY = 8, kNeedPlusZ = 16, kNeedMinusZ = 32,
  kSelfActive = 64, kInside = 128
};

struct VoxelUpdate {
  float speed;  // alpha D + (1 - alpha) H: the physical speed the CFL step is taken from
  float rate;   // F |grad phi|_upwind (F includes G_r): phi changes by dt * rate
};

// The unit normal's component across a voxel face: along, the difference across it; a and b, the
// central differences along the face (mean of the two voxels').
inline float faceNormal(float along, float a, float b) {
  const float len = std::sqrt(along * along + a * a + b * b);
  return len > 0 ? along / len : 0.0f;
}

// |grad phi| upwind for a front moving at speed: one square root, of the sum the sign picks.
inline float upwindGradient(float speed, float dxp, float dxm, float dyp, float dym, float dzp, float dzm) {
  auto sq = [](float v) { return v * v; };
  const float sumMax = sq(std::max(dxp, 0.0f)) + sq(std::max(-dxm, 0.0f)) + sq(std::max(dyp, 0.0f)) +
                       sq(std::max(-dym, 0.0f)) + sq(std::max(dzp, 0.0f)) + sq(std::max(-dzm, 0.0f));
  const float sumMin = sq(std::min(dxp, 0.0f)) + sq(std::min(-dxm, 0.0f)) + sq(std::min(dyp, 0.0f)) +
                       sq(std::min(-dym, 0.0f)) + sq(std::min(dzp, 0.0f)) + sq(std::min(-dzm, 0.0f));
  return std::sqrt(speed > 0 ? sumMax : sumMin);
}

// at(dx, dy, dz): phi at the neighbour (dx, dy, dz) in {-1, 0, 1}^3; intensity: I at the centre voxel.
template <class At>
inline VoxelUpdate evaluateVoxelAt(const At& at, float intensity, const SpeedParams& p) {
  const float c = at(0, 0, 0);
  const float dxp = at(1, 0, 0) - c, dxm = c - at(-1, 0, 0);
  const float dyp = at(0, 1, 0) - c, dym = c - at(0, -1, 0);
  const float dzp = at(0, 0, 1) - c, dzm = c - at(0, 0, -1);
  const float dx = 0.5f * (at(1, 0, 0) - at(-1, 0, 0));
  const float dy = 0.5f * (at(0, 1, 0) - at(0, -1, 0));
  const float dz = 0.5f * (at(0, 0, 1) - at(0, 0, -1));
  // Central differences one column/row/slice over, for the normals on the voxel's faces.
  const float dyAtXp = 0.5f * (at(1, 1, 0) - at(1, -1, 0)), dyAtXm = 0.5f * (at(-1, 1, 0) - at(-1, -1, 0));
  const float dzAtXp = 0.5f * (at(1, 0, 1) - at(1, 0, -1)), dzAtXm = 0.5f * (at(-1, 0, 1) - at(-1, 0, -1));
  const float dxAtYp = 0.5f * (at(1, 1, 0) - at(-1, 1, 0)), dxAtYm = 0.5f * (at(1, -1, 0) - at(-1, -1, 0));
  const float dzAtYp = 0.5f * (at(0, 1, 1) - at(0, 1, -1)), dzAtYm = 0.5f * (at(0, -1, 1) - at(0, -1, -1));
  const float dxAtZp = 0.5f * (at(1, 0, 1) - at(-1, 0, 1)), dxAtZm = 0.5f * (at(1, 0, -1) - at(-1, 0, -1));
  const float dyAtZp = 0.5f * (at(0, 1, 1) - at(0, -1, 1)), dyAtZm = 0.5f * (at(0, 1, -1) - at(0, -1, -1));
  const float nxp = faceNormal(dxp, 0.5f * (dyAtXp + dy), 0.5f * (dzAtXp + dz));
  const float nxm = faceNormal(dxm, 0.5f * (dyAtXm + dy), 0.5f * (dzAtXm + dz));
  const float nyp = faceNormal(dyp, 0.5f * (dxAtYp + dx), 0.5f * (dzAtYp + dz));
  const float nym = faceNormal(dym, 0.5f * (dxAtYm + dx), 0.5f * (dzAtYm + dz));
  const float nzp = faceNormal(dzp, 0.5f * (dxAtZp + dx), 0.5f * (dyAtZp + dy));
  const float nzm = faceNormal(dzm, 0.5f * (dxAtZm + dx), 0.5f * (dyAtZm + dy));
  const float curvature = 0.5f * ((nxp - nxm) + (nyp - nym) + (nzp - nzm));

  const float data = p.width - std::fabs(intensity - p.target);
  const float rescale = (c / kClamp) * (1.0f - std::sqrt(dx * dx + dy * dy + dz * dz));
  const float physical = p.alpha * data + (1.0f - p.alpha) * curvature;
  const float speed = physical + rescale;

  return {physical, speed * upwindGradient(speed, dxp, dxm, dyp, dym, dzp, dzm)};
}

// u: the 3x3x3 neighbourhood, u[(dz+1)*9 + (dy+1)*3 + (dx+1)].
inline VoxelUpdate evaluateVoxel(const float* u, float intensity, const SpeedParams& p) {
  return evaluateVoxelAt([u](int dx, int dy, int dz) { return u[(dz + 1) * 9 + (dy + 1) * 3 + (dx + 1)]; }, intensity, p);
}

// The time step from the CFL condition: the fastest voxel moves at most half a voxel per step (the
// upwind scheme's limit in 3D is 1/sqrt(3)). Its speed is bounded by the largest physical speed plus
// kRescaleSpeed, a bound on G_r where the band is a distance ramp. Taking G_r's largest value instead
// slows the front 3.5-fold (it is large only where the band is being rebuilt); leaving G_r out lets it
// overshoot (at half a voxel per step from the physical speed alone, the propagation test's front
// ran 7 % off and left gradient outside the band). The curvature term (parabolic) also stays within
// its explicit-scheme limit.
inline constexpr float kCflFraction = 0.5f;      // speed.glsl gets it as CFL_FRACTION
inline constexpr float kRescaleSpeed = 0.5f;     // speed.glsl: RESCALE_SPEED
inline constexpr float kCurvatureLimit = 0.25f;  // dt (1 - alpha) within it; speed.glsl: CURVATURE_LIMIT
// A page whose voxels' phi changed by no more than this (voxels) in an iteration, beside
// neighbours that did not either, is settled: it is not evaluated again until a page around it
// changes by more (level_set.h). A front that slow would need a thousand iterations to cross a voxel.
inline constexpr float kSettledChange = 1e-3f;  // the default; update.comp gets the LevelSet's as a uniform
inline float timeStep(float maxSpeed, float alpha) {
  float dt = kCflFraction / (maxSpeed + kRescaleSpeed);
  if (alpha < 1) dt = std::min(dt, kCurvatureLimit / (1.0f - alpha));
  return dt;
}

}  // namespace isoatlas::levelset
