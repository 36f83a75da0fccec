// IndexedHeap against a sorted reference: random sets, replacements and erasures, then every entry
// leaves in the reference's order.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "multires/indexed_heap.h"

namespace isoatlas::multires {
namespace {

struct Keyed {
  double key;
  std::uint32_t id;
};
struct IdOf {
  std::size_t operator()(const Keyed& k) const { return k.id; }
};
struct Less {
  bool operator()(const Keyed& a, const Keyed& b) const { return a.key != b.key ? a.key < b.key : a.id < b.id; }
};

TEST(IndexedHeap, EntriesLeaveInOrderAfterRandomSetsAndErasures) {
  constexpr std::uint32_t kIds = 300;
  IndexedHeap<Keyed, IdOf, Less> heap(kIds);
  std::map<std::uint32_t, double> current;  // the reference: id -> key
  std::mt19937 random(7);
  std::uniform_int_distribution<std::uint32_t> anyId(0, kIds - 1);
  std::uniform_int_distribution<int> anyKey(0, 50);  // few keys: many ties, broken by id
  for (int step = 0; step < 20000; ++step) {
    const std::uint32_t id = anyId(random);
    if (step % 5 == 4) {
      heap.erase(id);
      current.erase(id);
    } else {
      const double key = anyKey(random);
      heap.set({key, id});
      current[id] = key;
    }
    if (step % 997 == 0 && !current.empty()) {  // now and then the smallest leaves
      std::set<std::pair<double, std::uint32_t>> order;
      for (const auto& [i, k] : current) order.insert({k, i});
      const Keyed top = heap.pop();
      EXPECT_EQ(top.id, order.begin()->second);
      EXPECT_EQ(top.key, order.begin()->first);
      current.erase(top.id);
    }
  }
  std::set<std::pair<double, std::uint32_t>> order;
  for (const auto& [i, k] : current) order.insert({k, i});
  for (const auto& [key, id] : order) {
    ASSERT_FALSE(heap.empty());
    const Keyed top = heap.pop();
    EXPECT_EQ(top.id, id);
    EXPECT_EQ(top.key, key);
  }
  EXPECT_TRUE(heap.empty());
}

}  // namespace
}  // namespace isoatlas::multires
