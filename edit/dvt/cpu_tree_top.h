// The CPU tree above its bricks (cpu_tree_passes.cpp): a small index of nodes allocated in pairs of
// siblings, the last level's children a pair of bricks (cpu_brick.h).
#pragma once
#include <cstdint>
#include <vector>

#include "edit/dvt/cpu_brick.h"

namespace isoatlas::edit::dvt::cpu {

// The tree above the bricks: a small index of nodes allocated in pairs of siblings (children: the
// first of the pair; at the depth above the bricks, the first of a pair of bricks).
struct TopNode {
  std::uint32_t xy = 0, zd = 0;
  float value = kOutside;
  std::int32_t children = kNone;
  std::uint32_t mark = kMarkNone;
  Expansion expansion;
  Cell cell() const { return unpackCell(xy, zd); }
  bool leaf() const { return children < 0; }
};

// Slots allocated in pairs, freed pairs reused.
template <class T>
struct PairPool {
  std::vector<T> items;
  std::vector<std::int32_t> freePairs;
  std::int32_t allocate() {
    if (!freePairs.empty()) {
      const std::int32_t p = freePairs.back();
      freePairs.pop_back();
      return p;
    }
    items.resize(items.size() + 2);
    return std::int32_t(items.size() - 2);
  }
  void release(std::int32_t pair) {
    items[std::size_t(pair)] = T{}, items[std::size_t(pair) + 1] = T{};
    freePairs.push_back(pair);
  }
};

}  // namespace isoatlas::edit::dvt::cpu
