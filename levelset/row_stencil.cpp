#include "levelset/row_stencil.h"

#include <cstddef>

#include "core/cpu_dispatch.h"
#include "levelset/page_manager.h"

namespace isoatlas::levelset {
namespace {

// Row y of slice dz, from x = 0 (x = -1 and x = P are readable).
inline const float* rowAt(const float* apron, int side, int y, int dz) {
  return apron + std::size_t(((dz + 1) * side + y + 1) * side + 1);
}

}  // namespace

// GCC inlines faceNormal into the loops only when told to (flatten), and the loops stay scalar
// otherwise; clang refuses flatten beside target_clones, and inlines it of itself.
#if defined(__clang__) || defined(ISOATLAS_THREAD_SANITIZER)
#define ISOATLAS_ROW_LOOP ISOATLAS_CLONES("avx2")
#else
#define ISOATLAS_ROW_LOOP ISOATLAS_CLONES("avx2") __attribute__((flatten))
#endif

ISOATLAS_ROW_LOOP void rowFaceNormals(const float* __restrict apron, int side, int y0, int y1, int xEnd, float* __restrict faces) {
  for (int y = y0; y < y1; ++y) {
    const float *lo = rowAt(apron, side, y, 0), *hi = rowAt(apron, side, y + 1, 0);
    const float *loZm = rowAt(apron, side, y, -1), *loZp = rowAt(apron, side, y, 1);
    const float *hiZm = rowAt(apron, side, y + 1, -1), *hiZp = rowAt(apron, side, y + 1, 1);
    float* out = faces + std::size_t(y - y0) * kMaxPageSize;
    for (int x = 0; x < xEnd; ++x) {
      // As evaluateVoxelAt's nyp at (x, y): dyp, dxAtYp + dx, dzAtYp + dz (and its nym at (x, y + 1)).
      const float dxLo = 0.5f * (lo[x + 1] - lo[x - 1]), dxHi = 0.5f * (hi[x + 1] - hi[x - 1]);
      const float dzLo = 0.5f * (loZp[x] - loZm[x]), dzHi = 0.5f * (hiZp[x] - hiZm[x]);
      out[x] = faceNormal(hi[x] - lo[x], 0.5f * (dxHi + dxLo), 0.5f * (dzHi + dzLo));
    }
  }
}

ISOATLAS_ROW_LOOP void evaluateRows(const float* __restrict apron, int side, int y0, int y1, int xEnd,
                                    const float* __restrict intensity, std::size_t intensityStride, SpeedParams params,
                                    const float* __restrict faces, std::size_t stride, float* __restrict speed,
                                    float* __restrict rate, std::uint32_t* __restrict moving) {
  for (int y = y0; y < y1; ++y) {
    const float *c = rowAt(apron, side, y, 0), *ym = rowAt(apron, side, y - 1, 0), *yp = rowAt(apron, side, y + 1, 0);
    const float *zm = rowAt(apron, side, y, -1), *zp = rowAt(apron, side, y, 1);
    const float *zmYm = rowAt(apron, side, y - 1, -1), *zmYp = rowAt(apron, side, y + 1, -1);
    const float *zpYm = rowAt(apron, side, y - 1, 1), *zpYp = rowAt(apron, side, y + 1, 1);
    const float* below = faces + std::size_t(y - y0) * kMaxPageSize;
    const float* above = below + kMaxPageSize;
    const float* in = intensity + std::size_t(y - y0) * intensityStride;
    float* rowSpeed = speed + std::size_t(y - y0) * stride;
    float* rowRate = rate + std::size_t(y - y0) * stride;

    // Central dy and dz at x = -1 .. xEnd ([x + 1]), then the x faces: xFaces[x] lies between voxel
    // x - 1 and x, as evaluateVoxelAt's nxm at x and nxp at x - 1.
    float dyAt[kMaxPageSize + 2], dzAt[kMaxPageSize + 2], xFaces[kMaxPageSize + 1];
    for (int x = -1; x <= xEnd; ++x) {
      dyAt[x + 1] = 0.5f * (yp[x] - ym[x]);
      dzAt[x + 1] = 0.5f * (zp[x] - zm[x]);
    }
    for (int x = 0; x <= xEnd; ++x)
      xFaces[x] = faceNormal(c[x] - c[x - 1], 0.5f * (dyAt[x + 1] + dyAt[x]), 0.5f * (dzAt[x + 1] + dzAt[x]));

    for (int x = 0; x < xEnd; ++x) {
      const float cc = c[x];
      const float dxp = c[x + 1] - cc, dxm = cc - c[x - 1];
      const float dyp = yp[x] - cc, dym = cc - ym[x];
      const float dzp = zp[x] - cc, dzm = cc - zm[x];
      const float dx = 0.5f * (c[x + 1] - c[x - 1]), dy = dyAt[x + 1], dz = dzAt[x + 1];
      const float dxAtZp = 0.5f * (zp[x + 1] - zp[x - 1]), dxAtZm = 0.5f * (zm[x + 1] - zm[x - 1]);
      const float dyAtZp = 0.5f * (zpYp[x] - zpYm[x]), dyAtZm = 0.5f * (zmYp[x] - zmYm[x]);
      const float nzp = faceNormal(dzp, 0.5f * (dxAtZp + dx), 0.5f * (dyAtZp + dy));
      const float nzm = faceNormal(dzm, 0.5f * (dxAtZm + dx), 0.5f * (dyAtZm + dy));
      const float curvature = 0.5f * ((xFaces[x + 1] - xFaces[x]) + (above[x] - below[x]) + (nzp - nzm));

      const float data = params.width - std::fabs(in[x] - params.target);
      const float rescale = (cc / kClamp) * (1.0f - std::sqrt(dx * dx + dy * dy + dz * dz));
      const float physical = params.alpha * data + (1.0f - params.alpha) * curvature;
      const float s = physical + rescale;
      rowSpeed[x] = physical;
      rowRate[x] = s * upwindGradient(s, dxp, dxm, dyp, dym, dzp, dzm);
    }
    static_assert(kMaxPageSize <= 32, "a row's moving voxels are bits of a uint32");
    std::uint32_t rowMoving = 0;
    for (int x = 0; x < xEnd; ++x) rowMoving |= std::uint32_t(rowRate[x] != 0.0f) << x;
    moving[y - y0] = rowMoving;
  }
}

}  // namespace isoatlas::levelset
