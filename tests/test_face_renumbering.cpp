// The collapse loop's faces renamed without the dead ones (lib/src/simplify/face_renumbering.h):
// new ids in the order of the old, per-face entries moved with their face, the rest gone.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "simplify/face_renumbering.h"

namespace pm {
namespace {

TEST(FaceRenumbering, TheLiveFacesKeepTheirOrderAndTheDeadOnesGo) {
  const std::vector<uint8_t> dead = {0, 1, 0, 1, 1, 0};
  const FaceRenumbering faces(dead);
  const uint32_t gone = FaceRenumbering::kGone;
  EXPECT_EQ(faces.live, 3u);
  EXPECT_EQ(faces.new_id, (std::vector<uint32_t>{0, gone, 1, gone, gone, 2}));
  // Half-edge 3f + k follows its face.
  EXPECT_EQ(faces.half_edge(7), 4u);    // face 2, corner 1
  EXPECT_EQ(faces.half_edge(17), 8u);   // face 5, corner 2
  EXPECT_EQ(faces.half_edge(4), gone);  // face 1 is dead

  // Two entries per face.
  std::vector<int> values = {10, 11, 20, 21, 30, 31, 40, 41, 50, 51, 60, 61};
  faces.compact(values, 2);
  EXPECT_EQ(values, (std::vector<int>{10, 11, 30, 31, 60, 61}));
  // An array the caller left empty (a structure it does not use) stays empty.
  std::vector<int> unused;
  faces.compact(unused, 4);
  EXPECT_TRUE(unused.empty());
}

TEST(FaceRenumbering, NoDeadFaceChangesNothing) {
  const FaceRenumbering faces(std::vector<uint8_t>(4, 0));
  EXPECT_EQ(faces.live, 4u);
  std::vector<uint32_t> values = {7, 8, 9, 10};
  faces.compact(values, 1);
  EXPECT_EQ(values, (std::vector<uint32_t>{7, 8, 9, 10}));
}

// A large array shrunk in place keeps its first elements (its end's pages go back to the
// system, memory_pages.h; only the elements kept are read again).
TEST(FaceRenumbering, ALargeArrayShrinksInPlace) {
  std::vector<uint8_t> dead(1 << 20, 1);
  for (std::size_t f = 0; f < dead.size(); f += 7) dead[f] = 0;
  const FaceRenumbering faces(dead);
  std::vector<uint32_t> values(3 * dead.size());
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<uint32_t>(i);
  const uint32_t* storage = values.data();
  faces.compact(values, 3);
  ASSERT_EQ(values.size(), 3 * faces.live);
  EXPECT_EQ(values.data(), storage);  // no copy elsewhere
  for (std::size_t g = 0; g < faces.live; ++g)
    for (std::size_t k = 0; k < 3; ++k) ASSERT_EQ(values[3 * g + k], 3 * (7 * g) + k);
}

}  // namespace
}  // namespace pm
