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

VerticesBySquare::VerticesBySquare(const ChartGrid& grid, std::span<const ChartVertex> vertices)
    : s_(grid.squares()), squareOf_(vertices.size()), inSquare_(std::size_t(s_) * s_) {
  for (std::uint32_t d = 0; d < vertices.size(); ++d) {
    squareOf_[d] = grid.locate(vertices[d].chart, grid.guess(vertices[d].chart));
    inSquare_[squareOf_[d]].push_back(d);
  }
}

void VerticesBySquare::around(std::uint32_t i, std::uint32_t j, std::vector<std::uint32_t>& out) const {
  out.clear();
  for (const std::uint32_t sq : squaresAround(i, j))
    for (const std::uint32_t v : inSquare_[sq]) out.push_back(v);
}

void VerticesBySquare::moved(std::uint32_t i, std::uint32_t j, std::span<const std::uint32_t> vertices,
                             std::span<const std::uint32_t> squares) {
  for (const std::uint32_t sq : squaresAround(i, j)) inSquare_[sq].clear();
  for (std::size_t m = 0; m < vertices.size(); ++m) {
    squareOf_[vertices[m]] = squares[m];
    inSquare_[squares[m]].push_back(vertices[m]);
  }
}

}  // namespace isoatlas::atlas
