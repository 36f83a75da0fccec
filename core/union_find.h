// Disjoint sets over 0..n-1 with path halving: components of meshes and vertex fans.
#pragma once
#include <cstdint>
#include <numeric>
#include <vector>

namespace isoatlas {

struct UnionFind {
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) { parent[find(a)] = find(b); }
};

}  // namespace isoatlas
