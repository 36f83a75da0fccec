#include "multires/max_weight_matching.h"

#include <lemon/matching.h>
#include <lemon/smart_graph.h>

namespace isoatlas::multires {

std::vector<std::int64_t> maxWeightMatching(std::uint32_t nodes, const std::vector<WeightedEdge>& edges) {
  lemon::SmartGraph graph;
  graph.reserveNode(int(nodes));
  graph.reserveEdge(int(edges.size()));
  for (std::uint32_t i = 0; i < nodes; ++i) graph.addNode();
  lemon::SmartGraph::EdgeMap<std::int64_t> weight(graph);
  for (const WeightedEdge& e : edges)
    weight[graph.addEdge(graph.nodeFromId(int(e.a)), graph.nodeFromId(int(e.b)))] = e.weight;
  lemon::MaxWeightedMatching<lemon::SmartGraph, lemon::SmartGraph::EdgeMap<std::int64_t>> matching(graph, weight);
  matching.run();
  std::vector<std::int64_t> mate(nodes, -1);
  for (std::uint32_t i = 0; i < nodes; ++i) {
    const auto m = matching.mate(graph.nodeFromId(int(i)));
    if (m != lemon::INVALID) mate[i] = graph.id(m);
  }
  return mate;
}

}  // namespace isoatlas::multires
