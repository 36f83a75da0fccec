// maxWeightMatching: a maximum-weight matching of a graph with LEMON's blossom algorithm. Kept free
// of isoatlas headers because LEMON 1.3 compiles as C++17 only (this file's .cpp is built so).
#pragma once
#include <cstdint>
#include <vector>

namespace isoatlas::multires {

struct WeightedEdge {
  std::uint32_t a, b;
  std::int64_t weight;
};

// Inputs: the node count and the edges (weights >= 0). Output: per node its mate, or -1. Among the
// matchings of largest weight; give every edge a common large bonus to make it a largest matching first.
std::vector<std::int64_t> maxWeightMatching(std::uint32_t nodes, const std::vector<WeightedEdge>& edges);

}  // namespace isoatlas::multires
