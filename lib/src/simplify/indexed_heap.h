// A min-heap holding at most one key per id, each key changeable in place (an addressable
// priority queue), with four children per node: Johnson 1975, "Priority queues with update
// and finding minimum spanning trees" (d-heaps). A d-heap is shallower than a binary one,
// and with 12-byte entries a node's four children lie in one or two cache lines, which is
// what a heap of a million entries pays for. Updating in place, instead of pushing a new
// entry and skipping the stale ones when they surface, keeps the heap at one entry per id.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pm {

class IndexedHeap {
 public:
  explicit IndexedHeap(std::size_t ids) : position_(ids, kAbsent) {}

  bool empty() const { return entries_.empty(); }
  std::size_t size() const { return entries_.size(); }
  bool contains(uint32_t id) const { return position_[id] != kAbsent; }
  // The id of least key, ties to the smaller tie (set()'s; by default the id). Not empty.
  uint32_t top() const { return entries_.front().id; }
  // id's key. contains(id).
  float key(uint32_t id) const { return entries_[position_[id]].key; }
  // The id that comes to the top once top() leaves, if no key changes meanwhile: the least
  // of the top's children (the top itself when alone). Not empty.
  uint32_t runner_up() const {
    const std::size_t n = entries_.size();
    if (n < 2) return entries_.front().id;
    const std::size_t end = n < 1 + kArity ? n : 1 + kArity;
    std::size_t least = 1;
    for (std::size_t c = 2; c < end; ++c)
      if (less(entries_[c], entries_[least])) least = c;
    return entries_[least].id;
  }

  // Inserts id with `key`, or changes its key; among equal keys the smaller `tie` comes first.
  void set(uint32_t id, float key) { set(id, key, id); }
  void set(uint32_t id, float key, uint32_t tie) {
    if (position_[id] == kAbsent) {
      entries_.push_back({key, id, tie});
      position_[id] = static_cast<uint32_t>(entries_.size() - 1);
      sift_up(entries_.size() - 1);
      return;
    }
    const std::size_t i = position_[id];
    const Entry old = entries_[i];
    entries_[i].key = key;
    entries_[i].tie = tie;
    if (less(entries_[i], old)) {
      sift_up(i);
    } else {
      sift_down(i);
    }
  }

  // Removes every id (in the time of the ids present).
  void clear() {
    for (const Entry& e : entries_) position_[e.id] = kAbsent;
    entries_.clear();
  }
  // Appends every key present, in no order.
  void append_keys(std::vector<float>& out) const {
    for (const Entry& e : entries_) out.push_back(e.key);
  }
  // Removes id, if there.
  void erase(uint32_t id) {
    const uint32_t i = position_[id];
    if (i == kAbsent) return;
    position_[id] = kAbsent;
    const Entry last = entries_.back();
    entries_.pop_back();
    if (i == entries_.size()) return;
    place(i, last);
    if (i > 0 && less(last, entries_[(i - 1) / kArity])) {
      sift_up(i);
    } else {
      sift_down(i);
    }
  }

 private:
  static constexpr uint32_t kAbsent = 0xffffffffu;
  static constexpr std::size_t kArity = 4;
  struct Entry {
    float key;
    uint32_t id;
    uint32_t tie;
  };
  static bool less(const Entry& a, const Entry& b) {
    return a.key != b.key ? a.key < b.key : a.tie != b.tie ? a.tie < b.tie : a.id < b.id;
  }
  void place(std::size_t i, const Entry& e) {
    entries_[i] = e;
    position_[e.id] = static_cast<uint32_t>(i);
  }
  void sift_up(std::size_t i) {
    const Entry moving = entries_[i];
    while (i > 0) {
      const std::size_t parent = (i - 1) / kArity;
      if (!less(moving, entries_[parent])) break;
      place(i, entries_[parent]);
      i = parent;
    }
    place(i, moving);
  }
  void sift_down(std::size_t i) {
    const Entry moving = entries_[i];
    const std::size_t n = entries_.size();
    for (;;) {
      const std::size_t first = kArity * i + 1;
      if (first >= n) break;
      std::size_t least = first;
      const std::size_t end = first + kArity < n ? first + kArity : n;
      for (std::size_t c = first + 1; c < end; ++c)
        if (less(entries_[c], entries_[least])) least = c;
      if (!less(entries_[least], moving)) break;
      place(i, entries_[least]);
      i = least;
    }
    place(i, moving);
  }

  std::vector<Entry> entries_;
  std::vector<uint32_t> position_;  // per id: its index in entries_, or kAbsent
};

}  // namespace pm
