// A list of the collapse sequence's record entries (moved faces, corner ids), grown in
// fixed blocks and handed on whole: what a region's worker recorded becomes the sequence's
// without a copy.
//
// Why not a vector. The rounds' workers (simplifier.cpp, run_rounds()) each record their
// collapses until merge(), which interleaves them by bound. With vectors, merge() copied
// every entry into the sequence's vectors, reserved for the whole sequence up front: at the
// end of the first round, which makes most of the collapses, both were held at once, and
// each worker's doubling held an old array beside a new one. That was where pmenc's memory
// peaked (on the 950K-face textured mesh, 45 of its 421 MiB).
//
// A collapse asks for room first (make_room()): its entries then lie in one block, and a
// place (block * block size + offset) reads them all (at()). Places are what a Collapse
// keeps (moved_begin, new_faces_begin); take() moves another list's blocks after this one's
// and says how far their places moved. Lists that a collapse fills together (the moved
// faces and their texture-coordinate and normal ids) ask for the same room and receive the
// same number of entries, so their blocks and places agree.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

namespace pm {

// Entries per block: a moved-face list's (16 KiB), and a new-face list's (24 KiB, three ids a
// face). Each worker's last block is part empty until merge() fits it; with regions of
// 12,500 vertices (simplifier.cpp) the textured 950K-face mesh's rounds run 39 workers, five
// lists each, and blocks of 64 and 96 KiB took pmenc --fast's peak from 188.4 to 191.3 MiB
// (188.6 and 190.8 in a second run; tests/bench/textured.md: 187.9 -> 191.2, 1.49 times
// meshoptimizer's where issue 25 asks for 1.5); with these, 188.6 and 187.7, the same .pm.
constexpr uint32_t kMovedEntriesPerBlock = 1u << 12;
constexpr uint32_t kNewFaceEntriesPerBlock = 3u << 11;

class RecordList {
 public:
  // block_entries: entries per block (the new faces' lists: a multiple of 3, so that a
  // face's three ids start at a place divisible by 3).
  explicit RecordList(uint32_t block_entries) : block_(block_entries) {}

  // Makes sure the next `count` entries fit in the current block; a new block otherwise.
  // Throws std::length_error (encode(): kResourceLimit) when places would pass 2^32.
  void make_room(uint32_t count) {
    if (!blocks_.empty() && blocks_.back().used + count <= blocks_.back().capacity) return;
    add_block();
  }
  // After make_room() for at least this entry.
  void push_back(uint32_t x) {
    Block& b = blocks_.back();
    b.data[b.used++] = x;
  }
  // The place of the next entry.
  uint32_t end() const {
    return blocks_.empty() ? 0
                           : static_cast<uint32_t>((blocks_.size() - 1) * block_ + blocks_.back().used);
  }
  // The entries from `place` on, within its block.
  const uint32_t* at(uint32_t place) const { return blocks_[place / block_].data.get() + place % block_; }
  uint32_t* at(uint32_t place) { return blocks_[place / block_].data.get() + place % block_; }
  bool empty() const { return blocks_.empty(); }
  // The entries held (not end(): blocks may end with unused places).
  std::size_t count() const {
    std::size_t n = 0;
    for (const Block& b : blocks_) n += b.used;
    return n;
  }

  // Appends other's blocks (other is left empty) and returns what to add to a place of
  // other's to make it one of this list's. Other's last block gives back its unused room.
  uint32_t take(RecordList& other) {
    const uint32_t shift = static_cast<uint32_t>(blocks_.size() * block_);
    if (other.blocks_.empty()) return shift;
    check_places(blocks_.size() + other.blocks_.size());
    Block& last = other.blocks_.back();
    if (last.used < last.capacity) {
      std::unique_ptr<uint32_t[]> fitted(last.used ? new uint32_t[last.used] : nullptr);
      for (uint32_t i = 0; i < last.used; ++i) fitted[i] = last.data[i];
      last.data = std::move(fitted);
      last.capacity = last.used;
    }
    for (Block& b : other.blocks_) blocks_.push_back(std::move(b));
    other.blocks_.clear();
    return shift;
  }

  // Calls f(entries, count) for each block, in order (renaming, tests); from block `first`
  // on (block_count(): the blocks so far, which take() never changes).
  template <class F>
  void for_each_block(F&& f, std::size_t first = 0) {
    for (std::size_t i = first; i < blocks_.size(); ++i) f(blocks_[i].data.get(), blocks_[i].used);
  }
  std::size_t block_count() const { return blocks_.size(); }
  template <class F>
  void for_each_block(F&& f) const {
    for (const Block& b : blocks_) f(static_cast<const uint32_t*>(b.data.get()), b.used);
  }
  // Every entry in order (tests).
  std::vector<uint32_t> entries() const {
    std::vector<uint32_t> all;
    for_each_block([&](const uint32_t* x, uint32_t n) { all.insert(all.end(), x, x + n); });
    return all;
  }

 private:
  struct Block {
    std::unique_ptr<uint32_t[]> data;
    uint32_t used = 0, capacity = 0;
  };
  void check_places(std::size_t blocks) const {
    // The last block's places must stay below 2^32 (end() included).
    if (blocks >= (uint64_t{1} << 32) / block_)
      throw std::length_error("collapse record: more than 2^32 entries");
  }
  void add_block() {
    check_places(blocks_.size() + 1);
    blocks_.push_back({std::unique_ptr<uint32_t[]>(new uint32_t[block_]), 0, block_});
  }

  uint32_t block_;
  std::vector<Block> blocks_;
};

}  // namespace pm
