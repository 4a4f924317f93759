// loop_subdivide_keeping_attributes (big_mesh.h) on two literal triangles: Loop's positions,
// and texture coordinates whose seam along the shared edge stays a seam (two entries at the
// new vertex there) while a shared pair of entries stays shared. Built with the benchmarks
// only (PM_BUILD_BENCH and PM_BUILD_TESTS), so CI does not run it.
#include <gtest/gtest.h>

#include <array>
#include <set>

#include "big_mesh.h"

namespace {

// Two triangles in the plane z = 0 sharing the edge 1-2: (0, 1, 2) and (1, 3, 2).
pm::Mesh two_triangles(bool seam) {
  pm::Mesh mesh;
  mesh.positions = {0, 0, 0, 4, 0, 0, 0, 4, 0, 4, 4, 0};
  mesh.triangles = {0, 1, 2, 1, 3, 2};
  mesh.uvs = {0, 0, 1, 0, 0, 1, 1, 1};
  mesh.uv_indices = {0, 1, 2, 1, 3, 2};
  if (seam) {  // the second face has its own entries at 1 and 2
    mesh.uvs.insert(mesh.uvs.end(), {0.5f, 0, 0, 0.5f});
    mesh.uv_indices = {0, 1, 2, 4, 3, 5};
  }
  mesh.face_materials = {0, 1};
  mesh.material_names = {"a", "b"};
  return mesh;
}

std::array<float, 3> position(const pm::Mesh& mesh, uint32_t v) {
  return {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]};
}

// The texture coordinates at the corners of vertex v.
std::set<std::array<float, 2>> uvs_at(const pm::Mesh& mesh, uint32_t v) {
  std::set<std::array<float, 2>> out;
  for (std::size_t c = 0; c < mesh.triangles.size(); ++c)
    if (mesh.triangles[c] == v) {
      const uint32_t id = mesh.uv_indices[c];
      out.insert({mesh.uvs[2 * id], mesh.uvs[2 * id + 1]});
    }
  return out;
}

// The vertex at `where`; fails the test when none is.
uint32_t vertex_at(const pm::Mesh& mesh, std::array<float, 3> where) {
  for (uint32_t v = 0; v < mesh.vertex_count(); ++v)
    if (position(mesh, v) == where) return v;
  ADD_FAILURE() << "no vertex at " << where[0] << " " << where[1] << " " << where[2];
  return 0;
}

TEST(LoopKeepingAttributes, MovesPositionsByLoopsRules) {
  const pm::Mesh out = pm::bench::loop_subdivide_keeping_attributes(two_triangles(false), 1);
  ASSERT_EQ(out.face_count(), 8u);
  ASSERT_EQ(out.vertex_count(), 9u);  // 4 vertices and 5 edge points
  // Boundary corners: 3/4 of themselves and 1/8 of each boundary neighbour.
  EXPECT_EQ(position(out, 0), (std::array<float, 3>{0.5f, 0.5f, 0}));
  EXPECT_EQ(position(out, 1), (std::array<float, 3>{3.5f, 0.5f, 0}));
  // The shared edge's point: 3/8 of its ends and 1/8 of the opposite corners (all at 2, 2);
  // a boundary edge's point is its midpoint.
  vertex_at(out, {2, 2, 0});
  vertex_at(out, {2, 0, 0});
  // Each parent's material goes to its four children.
  EXPECT_EQ(out.face_materials, (std::vector<uint32_t>{0, 0, 0, 0, 1, 1, 1, 1}));
}

TEST(LoopKeepingAttributes, AUvSeamStaysASeamAndASharedEdgeStaysShared) {
  const pm::Mesh shared = pm::bench::loop_subdivide_keeping_attributes(two_triangles(false), 1);
  EXPECT_EQ(shared.uv_count(), 4u + 5u);  // one new entry per pair of entries along an edge
  EXPECT_EQ(uvs_at(shared, vertex_at(shared, {2, 2, 0})),
            (std::set<std::array<float, 2>>{{0.5f, 0.5f}}));

  const pm::Mesh seamed = pm::bench::loop_subdivide_keeping_attributes(two_triangles(true), 1);
  EXPECT_EQ(seamed.uv_count(), 6u + 6u);  // no pair shared: each face's three edges
  // Each face's own midpoint of its entries at 1 and 2: (1, 0)-(0, 1) and (0.5, 0)-(0, 0.5).
  EXPECT_EQ(uvs_at(seamed, vertex_at(seamed, {2, 2, 0})),
            (std::set<std::array<float, 2>>{{0.5f, 0.5f}, {0.25f, 0.25f}}));
  // An old vertex on the seam keeps its two entries.
  EXPECT_EQ(uvs_at(seamed, 1), (std::set<std::array<float, 2>>{{1, 0}, {0.5f, 0}}));
}

}  // namespace
