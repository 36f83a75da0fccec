// Quadric: Garland and Heckbert's error quadric, the sum of squared distances to a set of weighted
// planes, stored as the 10 coefficients of a symmetric 4x4 matrix plus the total weight (so that
// error / weight is a mean squared distance in mm^2).
#pragma once
#include "core/vec.h"

namespace isoatlas::multires {

struct Quadric {
  double a2 = 0, ab = 0, ac = 0, ad = 0, b2 = 0, bc = 0, bd = 0, c2 = 0, cd = 0, d2 = 0;
  double weight = 0;

  // The plane n.x + d = 0 (n of unit length), counted `w` times (e.g. the area of the face it holds).
  static Quadric plane(const Vec3& n, double d, double w) {
    Quadric q;
    q.a2 = w * n[0] * n[0], q.ab = w * n[0] * n[1], q.ac = w * n[0] * n[2], q.ad = w * n[0] * d;
    q.b2 = w * n[1] * n[1], q.bc = w * n[1] * n[2], q.bd = w * n[1] * d;
    q.c2 = w * n[2] * n[2], q.cd = w * n[2] * d, q.d2 = w * d * d;
    q.weight = w;
    return q;
  }
  Quadric& operator+=(const Quadric& o) {
    a2 += o.a2, ab += o.ab, ac += o.ac, ad += o.ad, b2 += o.b2, bc += o.bc, bd += o.bd;
    c2 += o.c2, cd += o.cd, d2 += o.d2, weight += o.weight;
    return *this;
  }
  friend Quadric operator+(Quadric a, const Quadric& b) { return a += b; }

  // Sum of weighted squared distances from p to the planes.
  double error(const Vec3& p) const {
    const double x = p[0], y = p[1], z = p[2];
    return a2 * x * x + 2 * ab * x * y + 2 * ac * x * z + 2 * ad * x + b2 * y * y + 2 * bc * y * z + 2 * bd * y +
           c2 * z * z + 2 * cd * z + d2;
  }
};

}  // namespace isoatlas::multires
