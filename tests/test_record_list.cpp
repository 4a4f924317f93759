// The collapse record's block lists (simplify/record_list.h): a collapse's entries stay in
// one block, places survive take(), and lists filled together keep the same places.
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "simplify/record_list.h"

namespace pm {
namespace {

// Appends `count` entries first, first + 1, ... as one collapse does; returns its place.
uint32_t record(RecordList& list, uint32_t first, uint32_t count) {
  list.make_room(count);
  const uint32_t place = list.end();
  for (uint32_t i = 0; i < count; ++i) list.push_back(first + i);
  return place;
}

TEST(RecordList, ACollapsesEntriesStayInOneBlock) {
  RecordList list(8);
  EXPECT_TRUE(list.empty());
  EXPECT_EQ(list.end(), 0u);
  EXPECT_EQ(record(list, 100, 5), 0u);
  // Three more fit beside the five (5 + 3 = 8).
  EXPECT_EQ(record(list, 200, 3), 5u);
  // The block is full: the next collapse starts the second block, at place 8.
  EXPECT_EQ(record(list, 300, 2), 8u);
  // Seven do not fit beside the two: the third block, at place 16, leaving 10..15 unused.
  EXPECT_EQ(record(list, 400, 7), 16u);
  EXPECT_EQ(list.end(), 23u);
  EXPECT_EQ(list.count(), 17u);
  EXPECT_EQ(list.at(5)[2], 202u);
  EXPECT_EQ(list.at(8)[1], 301u);
  EXPECT_EQ(list.at(16)[6], 406u);
  EXPECT_EQ(list.entries(), (std::vector<uint32_t>{100, 101, 102, 103, 104, 200, 201, 202, 300,
                                                   301, 400, 401, 402, 403, 404, 405, 406}));
}

TEST(RecordList, TakeMovesTheOtherListsBlocksAndSaysHowFarTheirPlacesMoved) {
  RecordList sequence(8), worker(8);
  record(sequence, 10, 6);
  record(sequence, 20, 4);  // the second block: sequence has two
  const uint32_t a = record(worker, 30, 3);
  const uint32_t b = record(worker, 40, 6);  // worker's second block
  const uint32_t shift = sequence.take(worker);
  EXPECT_EQ(shift, 16u);
  EXPECT_TRUE(worker.empty());
  EXPECT_EQ(sequence.at(a + shift)[0], 30u);
  EXPECT_EQ(sequence.at(b + shift)[5], 45u);
  EXPECT_EQ(sequence.count(), 19u);
  // The worker's last block gave back its room: nothing more fits there, so a new entry
  // starts a block of its own after it.
  EXPECT_EQ(record(sequence, 50, 1), 32u);
  EXPECT_EQ(sequence.at(24)[5], 45u);
  // The worker starts afresh, its places from 0 again.
  EXPECT_EQ(record(worker, 60, 2), 0u);
  EXPECT_EQ(sequence.take(worker), 40u);
  EXPECT_EQ(sequence.at(40)[1], 61u);
  EXPECT_EQ(sequence.entries(), (std::vector<uint32_t>{10, 11, 12, 13, 14, 15, 20, 21, 22, 23, 30,
                                                       31, 32, 40, 41, 42, 43, 44, 45, 50, 60, 61}));
}

TEST(RecordList, ListsFilledTogetherKeepTheSamePlaces) {
  // The moved faces and their texture-coordinate ids: the same room asked, as many entries.
  RecordList faces(kMovedEntriesPerBlock), uvs(kMovedEntriesPerBlock);
  for (uint32_t k = 0; k < 20000; ++k) {
    const uint32_t room = 3 + k % 11, moved = k % 7;
    faces.make_room(room);
    uvs.make_room(room);
    ASSERT_EQ(faces.end(), uvs.end());
    for (uint32_t i = 0; i < moved; ++i) faces.push_back(k), uvs.push_back(k + 1);
  }
  RecordList sequence_faces(kMovedEntriesPerBlock), sequence_uvs(kMovedEntriesPerBlock);
  record(sequence_faces, 0, 5);
  record(sequence_uvs, 0, 5);
  EXPECT_EQ(sequence_faces.take(faces), sequence_uvs.take(uvs));
  EXPECT_EQ(sequence_faces.end(), sequence_uvs.end());
  EXPECT_EQ(sequence_faces.count(), sequence_uvs.count());
}

TEST(RecordList, NewFacePlacesAreWholeFaces) {
  // Three ids a face, two faces at most a collapse: a block of 3 * 2^13 ids ends on a face.
  RecordList ids(kNewFaceEntriesPerBlock);
  for (uint32_t k = 0; k < 10000; ++k) {
    ids.make_room(6);
    ASSERT_EQ(ids.end() % 3, 0u);
    for (uint32_t i = 0; i < 3 * (1 + k % 2); ++i) ids.push_back(k);
  }
  EXPECT_EQ(ids.count(), 3u * 15000u);
}

TEST(RecordList, RefusesPlacesPast32Bits) {
  // One block of 2^32 - 1 entries would already leave no place for a second: refused before
  // anything is allocated.
  RecordList huge(0xFFFFFFFFu);
  EXPECT_THROW(huge.make_room(1), std::length_error);
  EXPECT_TRUE(huge.empty());
}

}  // namespace
}  // namespace pm
