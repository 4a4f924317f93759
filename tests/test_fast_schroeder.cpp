// Issue 25: the collapse loop (the former fast loop; one since issue 25) with Schroeder's
// metric (EncodeOptions{Metric::kSchroeder}, schroeder_costs.cpp), with the former default
// loop's rules: a boundary vertex goes only along its boundary edges (Schroeder, Zarge and
// Lorensen 1992, §3.1), --keep-corners keeps corners, full detail is the input exactly, and
// regions make the same .pm for any number of threads. The loops' shared properties
// (topology, --faces, error order, attributes) are checked for it with the other loops in
// test_encoder.cpp (EveryMesh) and test_attributes.cpp.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/pm_codec.h"
#include "test_util.h"

namespace pm {
namespace {

EncodeOptions fast_schroeder() {
  EncodeOptions options;
  options.metric = Metric::kSchroeder;
  return options;
}

// A flat (cells x cells) grid over [0, cells]^2, its diagonals alternating: every boundary
// vertex has two boundary edges and no feature edge (kind kBoundary).
Mesh flat_grid(int cells) {
  Mesh grid;
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) grid.positions.insert(grid.positions.end(), {float(i), float(j), 0.0f});
  auto at = [&](int i, int j) { return uint32_t(j * (cells + 1) + i); };
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      const uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if ((i + j) % 2 == 0)
        grid.triangles.insert(grid.triangles.end(), {a, b, c, a, c, d});
      else
        grid.triangles.insert(grid.triangles.end(), {a, b, d, b, c, d});
    }
  return grid;
}

// A cube [-1, 1]^3, each side a (cells x cells) grid, vertices shared along its edges: its
// 8 corners have three feature edges each (corners), its edges' other vertices two.
Mesh grid_cube(int cells) {
  Mesh cube;
  std::map<std::array<int, 3>, uint32_t> ids;
  auto vertex = [&](std::array<int, 3> p) {
    const auto [it, added] = ids.emplace(p, uint32_t(ids.size()));
    if (added)
      for (int k = 0; k < 3; ++k) cube.positions.push_back(2.0f * float(p[k]) / float(cells) - 1.0f);
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side <= 1; ++side) {
      const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
      auto at = [&](int i, int j) {
        std::array<int, 3> p{};
        p[axis] = side * cells;
        p[a1] = i;
        p[a2] = j;
        return vertex(p);
      };
      for (int j = 0; j < cells; ++j)
        for (int i = 0; i < cells; ++i) {
          const uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
          // Outward: counter-clockwise seen from outside on the far side, the other way near.
          if (side == 1)
            cube.triangles.insert(cube.triangles.end(), {a, b, c, a, c, d});
          else
            cube.triangles.insert(cube.triangles.end(), {a, c, b, a, d, c});
        }
    }
  return cube;
}

ProgressiveMesh encode_ok(const Mesh& input, const EncodeOptions& options) {
  ProgressiveMesh pm;
  EncodeStats stats;
  const Status status = encode(input, options, pm, &stats);
  EXPECT_TRUE(status.ok()) << status.message();
  EXPECT_TRUE(test::ok(validate(pm)));
  return pm;
}

TEST(FastSchroeder, RunsTheFastLoop) {
  ProgressiveMesh pm;
  EncodeStats stats;
  ASSERT_TRUE(encode(flat_grid(4), fast_schroeder(), pm, &stats).is_ok());
  EXPECT_EQ(stats.collapses, pm.split_count());
  EXPECT_GT(stats.collapses, 0u);
}

// A bumpy (cells x cells) grid whose boundary zigzags: every other vertex of each side is
// pushed inwards, so that the vertices between them sit in notches, where moving one along
// the boundary may turn a face over while an interior edge would be legal.
Mesh zigzag_grid(int cells) {
  Mesh grid = flat_grid(cells);
  for (std::size_t v = 0; v < grid.vertex_count(); ++v) {
    float* p = &grid.positions[3 * v];
    const int i = int(p[0]), j = int(p[1]);
    if ((i + j) % 2 == 1) {
      if (j == 0) p[1] += 0.45f;
      if (j == cells) p[1] -= 0.45f;
      if (i == 0) p[0] += 0.45f;
      if (i == cells) p[0] -= 0.45f;
    }
    p[2] = 0.8f * std::sin(1.3f * p[0]) * std::cos(1.1f * p[1]);
  }
  return grid;
}

// At each level of the stream, the vertex its last split made, v, if on the boundary, must
// have come apart from u along a boundary edge (one face on v-u): a boundary vertex is
// collapsed only along its boundary edges. For both the one-heap and the regions' loop.
// (The special edges are tried first anyway; only where they are illegal does the rule
// decide: with boundary vertices allowed every edge and interior ones tried first, this
// fails at dozens of levels.)
TEST(FastSchroeder, BoundaryVerticesCollapseOnlyAlongTheBoundary) {
  for (const Mesh& input : {flat_grid(12), zigzag_grid(12)}) {
    for (const std::size_t partition : {std::size_t{0}, std::size_t{1}}) {
      SCOPED_TRACE(std::to_string(input.vertex_count()) + " vertices, partition " +
                   std::to_string(partition));
      EncodeOptions options = fast_schroeder();
      options.feature_angle_deg = 180;  // boundaries only: the bumps make no corners
      options.fast_partition_vertices = partition;
      options.threads = 2;
      const ProgressiveMesh pm = encode_ok(input, options);
      std::vector<std::size_t> levels;
      for (std::size_t level = 1; level <= pm.splits.size(); ++level) levels.push_back(level);
      std::size_t boundary_splits = 0;
      extract_levels(pm, levels, [&](std::size_t level, const Mesh& lod) {
        // No vertex is dropped: vertex ids are the stream's.
        ASSERT_EQ(lod.vertex_count(), pm.base_vertex_count + level);
        const uint32_t v = static_cast<uint32_t>(lod.vertex_count() - 1);
        const uint32_t u = pm.splits[level - 1].u;
        std::map<uint32_t, int> faces_on_edge_to;  // v's neighbours: faces on the edge to each
        for (std::size_t f = 0; f < lod.face_count(); ++f)
          for (int c = 0; c < 3; ++c)
            if (lod.triangles[3 * f + c] == v) {
              ++faces_on_edge_to[lod.triangles[3 * f + (c + 1) % 3]];
              ++faces_on_edge_to[lod.triangles[3 * f + (c + 2) % 3]];
            }
        bool on_boundary = false;
        for (const auto& [w, n] : faces_on_edge_to) on_boundary |= n == 1;
        if (!on_boundary) return;
        ++boundary_splits;
        EXPECT_EQ(faces_on_edge_to[u], 1)
            << "level " << level << ": boundary vertex " << v << " came from " << u
            << " across an interior edge";
      });
      EXPECT_GT(boundary_splits, input.vertex_count() / 4);
    }
  }
}

// The cube's 8 corners are in its base mesh with keep_corners; without, the base mesh (at
// most a tetrahedron's 4 vertices) has lost some.
TEST(FastSchroeder, KeepCornersKeepsTheCorners) {
  const Mesh cube = grid_cube(4);
  auto corners_in_base = [](const ProgressiveMesh& pm) {
    int found = 0;
    for (uint32_t v = 0; v < pm.base_vertex_count; ++v) {
      const float* p = &pm.positions[3 * std::size_t{v}];
      found += std::abs(p[0]) == 1 && std::abs(p[1]) == 1 && std::abs(p[2]) == 1;
    }
    return found;
  };
  EncodeOptions options = fast_schroeder();
  options.keep_corners = true;
  const ProgressiveMesh kept = encode_ok(cube, options);
  EXPECT_EQ(corners_in_base(kept), 8);
  EXPECT_LT(kept.base_vertex_count, cube.vertex_count() / 2);  // it did simplify
  EXPECT_LT(corners_in_base(encode_ok(cube, fast_schroeder())), 8);
}

// Full detail is the input exactly: positions, faces, and every corner attribute.
TEST(FastSchroeder, FullDetailIsTheInputExactly) {
  for (const Mesh& input : {test::seamed_grid(16), grid_cube(5), flat_grid(9)}) {
    for (const std::size_t partition : {std::size_t{0}, std::size_t{1}}) {
      EncodeOptions options = fast_schroeder();
      options.fast_partition_vertices = partition;
      const ProgressiveMesh pm = encode_ok(input, options);
      const Mesh full = extract_level(pm, pm.split_count());
      EXPECT_TRUE(test::same_attributed_faces(input, full)) << "partition " << partition;
      EXPECT_EQ(full.vertex_count(), input.vertex_count());
      EXPECT_LT(pm.base_face_count(), input.face_count() / 4);
    }
  }
}

// In regions (forced: fast_partition_vertices 1), the .pm is the same on one thread and on
// two; and not the one heap's, so the regions did run.
TEST(FastSchroeder, RegionsMakeTheSameStreamForAnyThreadCount) {
  // Over the unit square, as test_encoder.cpp's bumpy_grid (with a grid far thicker than
  // it is wide, the Morton regions' cuts hold too many vertices, and one heap runs).
  Mesh bumpy = flat_grid(260);
  for (std::size_t v = 0; v < bumpy.vertex_count(); ++v) {
    float* p = &bumpy.positions[3 * v];
    const float x = p[0] / 260, y = p[1] / 260;
    p[0] = x;
    p[1] = y;
    p[2] = 0.1f * std::sin(9 * x) * std::cos(7 * y) + 0.02f * std::sin(40 * x * y);
  }
  auto stream = [&](std::size_t partition, unsigned threads) {
    EncodeOptions options = fast_schroeder();
    options.fast_partition_vertices = partition;
    options.threads = threads;
    std::string bytes;
    EXPECT_TRUE(write_pm(encode_ok(bumpy, options), WriteOptions{}, bytes).is_ok());
    return bytes;
  };
  const std::string one_thread = stream(1, 1);
  EXPECT_TRUE(stream(1, 2) == one_thread) << "two threads made another stream";
  EXPECT_TRUE(stream(0, 1) != one_thread) << "the regions did not run";
}

}  // namespace
}  // namespace pm
