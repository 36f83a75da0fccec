// IndexedHeap: a binary min-heap holding at most one entry per id (0 .. ids - 1), with each id's place
// kept, so that an entry is replaced in place (one sift, where a remove and an insert take two) or
// removed in O(log n).
//
// Inputs: `Entry` values; `IdOf(entry)` its id; `Less(a, b)` a strict total order (ties broken, e.g.
// by id), so that the entries leave in one order whatever the order they came in.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

namespace isoatlas::multires {

template <class Entry, class IdOf, class Less>
class IndexedHeap {
public:
  explicit IndexedHeap(std::size_t ids = 0) : place_(ids, kAbsent) {}

  bool empty() const { return heap_.empty(); }
  const Entry& top() const { return heap_.front(); }

  Entry pop() {
    Entry first = heap_.front();
    erase(IdOf{}(first));
    return first;
  }

  // Inserts the entry, or replaces the one of its id.
  void set(const Entry& entry) {
    const std::size_t id = IdOf{}(entry);
    if (place_[id] == kAbsent) {
      place_[id] = std::uint32_t(heap_.size());
      heap_.push_back(entry);
      siftUp(heap_.size() - 1);
      return;
    }
    replace(place_[id], entry);
  }

  // Removes the entry of the id, if there is one.
  void erase(std::size_t id) {
    if (place_[id] == kAbsent) return;
    const std::size_t at = place_[id];
    place_[id] = kAbsent;
    Entry last = std::move(heap_.back());
    heap_.pop_back();
    if (at < heap_.size()) replace(at, std::move(last));
  }

private:
  static constexpr std::uint32_t kAbsent = ~0u;

  // The entry at `at` becomes `entry`, sifted up or down to its place.
  void replace(std::size_t at, Entry entry) {
    const bool rises = Less{}(entry, heap_[at]);
    heap_[at] = std::move(entry);
    rises ? siftUp(at) : siftDown(at);
  }
  void put(std::size_t at, Entry entry) {
    place_[IdOf{}(entry)] = std::uint32_t(at);
    heap_[at] = std::move(entry);
  }
  void siftUp(std::size_t at) {
    Entry moving = std::move(heap_[at]);
    while (at > 0) {
      const std::size_t parent = (at - 1) / 2;
      if (!Less{}(moving, heap_[parent])) break;
      put(at, std::move(heap_[parent]));
      at = parent;
    }
    put(at, std::move(moving));
  }
  void siftDown(std::size_t at) {
    if (at >= heap_.size()) return;
    Entry moving = std::move(heap_[at]);
    for (;;) {
      std::size_t child = 2 * at + 1;
      if (child >= heap_.size()) break;
      if (child + 1 < heap_.size() && Less{}(heap_[child + 1], heap_[child])) ++child;
      if (!Less{}(heap_[child], moving)) break;
      put(at, std::move(heap_[child]));
      at = child;
    }
    put(at, std::move(moving));
  }

  std::vector<Entry> heap_;
  std::vector<std::uint32_t> place_;  // per id, its entry's place in heap_, or kAbsent
};

}  // namespace isoatlas::multires
