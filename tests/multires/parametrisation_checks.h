// The parametrisation's invariants, shared by the simplification and pairing tests: every dense
// vertex has a base triangle and barycentric weights inside it (>= 0, summing to one) whose point
// on the base mesh lies within `tolerance` of the vertex.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>

#include "multires/base_mesh.h"

namespace isoatlas::test {

inline void expectParametrisationInside(const Mesh& dense, const multires::BaseMesh& base, double tolerance) {
  ASSERT_EQ(base.denseTriangle.size(), dense.vertexCount());
  double worst = 0;
  for (std::size_t d = 0; d < dense.vertexCount(); ++d) {
    const auto& b = base.denseBary[d];
    ASSERT_LT(base.denseTriangle[d], base.triangleCount());
    EXPECT_GE(std::min({b[0], b[1], b[2]}), 0.0) << "dense vertex " << d;
    EXPECT_NEAR(b[0] + b[1] + b[2], 1.0, 1e-9);
    worst = std::max(worst, norm(base.pointAt(base.denseTriangle[d], b) - dense.positions[d]));
  }
  EXPECT_LT(worst, tolerance) << "a dense vertex's image on the base mesh lies too far from it";
}

}  // namespace isoatlas::test
