#include "atlas/chart_grid.h"

namespace isoatlas::atlas {

double largestVertexError(const ChartGrid& grid, std::span<const ChartVertex> vertices) {
  double largest = 0;
  std::uint32_t square = 0;
  for (const ChartVertex& v : vertices) {
    square = grid.locate(v.chart, square);  // the vertices come tile by tile, near each other
    largest = std::max(largest, norm(v.position - grid.pointAt(v.chart, square)));
  }
  return largest;
}

}  // namespace isoatlas::atlas
