#include "multires/folded_dense_triangles.h"

#include <limits>

#include "core/error.h"
#include "multires/base_domain.h"

namespace isoatlas::multires {
namespace {

// Twice the signed area of a dense triangle's image in one chart that holds its corners (a base
// triangle's own frame has area 1 in these units; the other frames that hold the image are affine
// images of it, so the sign holds there too); -inf when its corners share no chart.
double imageArea(const Mesh& dense, const BaseDomain& domain, std::size_t face, BaseDomain::Chart& chart) {
  std::array<BaseDomain::Point2, 3> p;
  if (!domain.chartDenseTriangle(dense.face(face), chart, p)) return -std::numeric_limits<double>::infinity();
  return orient2(p[0], p[1], p[2]);
}

constexpr double kFlat = 1e-14;

}  // namespace

std::size_t countFoldedTriangles(const Mesh& dense, const BaseMesh& base) {
  require(base.denseTriangle.size() == dense.vertexCount(), "folded triangles: the parametrisation does not match the mesh");
  require(dense.allFacesHave(3), "folded triangles: the dense mesh must be made of triangles");
  const BaseDomain domain(base);
  BaseDomain::Chart chart;
  std::size_t folded = 0;
  for (std::size_t f = 0; f < dense.faceCount(); ++f) folded += imageArea(dense, domain, f, chart) <= kFlat;
  return folded;
}

}  // namespace isoatlas::multires
