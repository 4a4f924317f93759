// The collapse loop's addressable heap (lib/src/simplify/indexed_heap.h): least key first, ties to
// the smaller tie given or else the smaller id, keys changed and ids removed in place, against a
// sorted reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "simplify/indexed_heap.h"

namespace pm {
namespace {

std::vector<uint32_t> drain(IndexedHeap& heap) {
  std::vector<uint32_t> order;
  while (!heap.empty()) {
    const uint32_t id = heap.top();
    order.push_back(id);
    heap.erase(id);
  }
  return order;
}

TEST(IndexedHeap, LeastKeyFirstTiesToTheSmallerId) {
  IndexedHeap heap(8);
  heap.set(5, 2.0f);
  heap.set(1, 3.0f);
  heap.set(7, 2.0f);
  heap.set(0, 9.0f);
  heap.set(3, -1.0f);
  EXPECT_EQ(heap.size(), 5u);
  EXPECT_EQ(heap.key(7), 2.0f);
  EXPECT_EQ(drain(heap), (std::vector<uint32_t>{3, 5, 7, 1, 0}));
  EXPECT_TRUE(heap.empty());
}

TEST(IndexedHeap, SetChangesAKeyInPlaceAndEraseRemovesAnyId) {
  IndexedHeap heap(6);
  for (uint32_t id = 0; id < 6; ++id) heap.set(id, float(id));
  heap.set(4, -5.0f);  // up
  heap.set(0, 10.0f);  // down
  heap.set(2, 2.0f);   // the same key
  heap.erase(3);
  heap.erase(3);  // absent: nothing
  EXPECT_FALSE(heap.contains(3));
  EXPECT_TRUE(heap.contains(4));
  EXPECT_EQ(heap.size(), 5u);
  EXPECT_EQ(drain(heap), (std::vector<uint32_t>{4, 1, 2, 5, 0}));
}

// With a tie given, equal keys go by it (the collapse loop gives a counter: oldest first), and
// only equal ties by the id.
TEST(IndexedHeap, EqualKeysGoByTheTieGivenThenByTheId) {
  IndexedHeap heap(6);
  heap.set(0, 1.0f, 30);
  heap.set(1, 1.0f, 10);
  heap.set(2, 1.0f, 20);
  heap.set(3, 0.5f, 99);
  heap.set(4, 1.0f, 10);
  heap.set(5, 1.0f, 40);
  heap.set(5, 1.0f, 5);  // the same key, a new tie: moves up
  EXPECT_EQ(heap.runner_up(), 5u);
  EXPECT_EQ(drain(heap), (std::vector<uint32_t>{3, 5, 1, 4, 2, 0}));
}

// Thousands of random sets and erases, checked after each against a std::map of
// (key, id) -> the same top, the same size.
TEST(IndexedHeap, AgreesWithASortedReferenceUnderRandomUpdates) {
  constexpr uint32_t kIds = 500;
  IndexedHeap heap(kIds);
  std::map<std::pair<float, uint32_t>, bool> reference;
  std::vector<float> key_of(kIds, 0.0f);
  std::vector<bool> present(kIds, false);
  std::mt19937 random(12345);
  for (int step = 0; step < 20000; ++step) {
    const uint32_t id = random() % kIds;
    if (random() % 4 == 0) {
      heap.erase(id);
      if (present[id]) reference.erase({key_of[id], id});
      present[id] = false;
    } else {
      const float key = float(random() % 100);  // many ties
      heap.set(id, key);
      if (present[id]) reference.erase({key_of[id], id});
      reference[{key, id}] = true;
      key_of[id] = key;
      present[id] = true;
    }
    ASSERT_EQ(heap.size(), reference.size());
    if (!reference.empty()) {
      ASSERT_EQ(heap.top(), reference.begin()->first.second) << "step " << step;
      ASSERT_EQ(heap.key(heap.top()), reference.begin()->first.first);
      // The runner-up: the second of the order (the top itself when alone).
      const auto second = reference.size() > 1 ? std::next(reference.begin()) : reference.begin();
      ASSERT_EQ(heap.runner_up(), second->first.second) << "step " << step;
    }
  }
}

}  // namespace
}  // namespace pm
