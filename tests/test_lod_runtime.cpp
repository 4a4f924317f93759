// The runtime LOD object (Hoppe 1998): refining and coarsening in place, by steps and by
// jumps, always gives what a fresh decode to that level gives; geomorphs (Hoppe 1996, §4.2)
// start at the coarse level's geometry and end at the fine one's.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <type_traits>
#include <string>

#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/lod_runtime.h"
#include "pm/mesh_io.h"
#include "test_meshes.h"
#include "test_util.h"

namespace pm {
namespace {

ProgressiveMesh encode_ok(const Mesh& mesh) {
  ProgressiveMesh pm;
  const Status status = encode(mesh, EncodeOptions{}, pm);
  EXPECT_TRUE(status.ok()) << status.message();
  return pm;
}

::testing::AssertionResult matches_fresh_decode(const RuntimeLod& lod, const ProgressiveMesh& pm) {
  const Mesh fresh = extract_level(pm, lod.level());
  if (lod.face_count() != fresh.face_count())
    return ::testing::AssertionFailure() << "level " << lod.level() << ": " << lod.face_count()
                                         << " faces, fresh decode " << fresh.face_count();
  if (lod.vertex_count() != vertices_at_level(pm, lod.level()))
    return ::testing::AssertionFailure() << "level " << lod.level() << ": vertex count "
                                         << lod.vertex_count();
  for (std::size_t i = 0; i < 3 * lod.face_count(); ++i)
    if (lod.indices()[i] >= lod.wedge_count())
      return ::testing::AssertionFailure() << "index " << i << " beyond wedge_count()";
  auto result = test::same_attributed_faces(fresh, lod.to_mesh());
  if (!result) result << "\n  at level " << lod.level();
  return result;
}

// Every level, down and up by single steps, then random jumps both ways.
void check_steps_and_jumps(const ProgressiveMesh& pm, std::size_t step, int jumps) {
  RuntimeLod lod(pm);
  ASSERT_EQ(lod.level(), 0u);
  ASSERT_TRUE(matches_fresh_decode(lod, pm));
  lod.set_level(lod.max_level());
  ASSERT_TRUE(matches_fresh_decode(lod, pm));
  for (std::size_t level = lod.max_level(); level > 0;) {
    level = level > step ? level - step : 0;
    lod.set_level(level);
    ASSERT_TRUE(matches_fresh_decode(lod, pm));
  }
  for (std::size_t level = 0; level < lod.max_level();) {
    level = std::min(level + step, lod.max_level());
    lod.set_level(level);
    ASSERT_TRUE(matches_fresh_decode(lod, pm));
  }
  std::mt19937 random(7);
  std::uniform_int_distribution<std::size_t> any_level(0, lod.max_level());
  for (int j = 0; j < jumps; ++j) {
    lod.set_level(any_level(random));
    ASSERT_TRUE(matches_fresh_decode(lod, pm));
  }
}

TEST(RuntimeLod, StepsAndJumpsMatchAFreshDecodeWithAttributes) {
  check_steps_and_jumps(encode_ok(test::seamed_grid(16)), 1, 60);
}

class RuntimeLodReal : public ::testing::TestWithParam<test::TestMesh> {};

TEST_P(RuntimeLodReal, StepsAndJumpsMatchAFreshDecode) {
  PM_SKIP_IF_MISSING(GetParam());
  Mesh mesh;
  ASSERT_TRUE(read_mesh(GetParam().path, mesh).ok());
  const ProgressiveMesh pm = encode_ok(mesh);
  // About 25 stops each way and 12 jumps, each compared face by face with a fresh decode
  // (the samples: welds, carried faces, loose vertices, polygons).
  check_steps_and_jumps(pm, std::max<std::size_t>(1, pm.split_count() / 25), 12);
}

INSTANTIATE_TEST_SUITE_P(Meshes, RuntimeLodReal, ::testing::ValuesIn(test::all_test_meshes()),
                         test::test_mesh_name);

TEST(RuntimeLod, FaceVertexAndErrorRequestsPickTheLevelsOfLod) {
  const ProgressiveMesh pm = encode_ok(test::seamed_grid(16));
  RuntimeLod lod(pm);
  for (std::size_t n : {std::size_t{0}, std::size_t{5}, std::size_t{100}, std::size_t{301},
                        std::size_t{1000000}}) {
    lod.set_face_count(n);
    EXPECT_EQ(lod.level(), level_for_faces(pm, n)) << n;
    lod.set_vertex_count(n);
    EXPECT_EQ(lod.level(), level_for_vertices(pm, n)) << n;
  }
  for (std::size_t level : {std::size_t{0}, pm.split_count() / 2, pm.split_count() - 1}) {
    const double e = error_at_level(pm, level);
    lod.set_error(e);
    EXPECT_EQ(lod.level(), level_for_error(pm, e)) << e;
  }
}

TEST(RuntimeLod, ActiveWedgesAndFacesArePrefixes) {
  const ProgressiveMesh pm = encode_ok(test::seamed_grid(16));
  RuntimeLod lod(pm);
  std::size_t previous_faces = 0, previous_wedges = 0;
  for (std::size_t level = 0; level <= lod.max_level(); ++level) {
    lod.set_level(level);
    EXPECT_GE(lod.face_count(), previous_faces);
    EXPECT_GE(lod.wedge_count(), previous_wedges);
    previous_faces = lod.face_count();
    previous_wedges = lod.wedge_count();
  }
  EXPECT_GT(lod.memory_bytes(), 0u);
}

// A renderer that keeps the active indices uploads only the range set_level reports: its copy
// is then the active prefix exactly, by steps and by jumps both ways.
TEST(RuntimeLod, SetLevelReportsTheIndicesItRewrote) {
  const ProgressiveMesh pm = encode_ok(test::seamed_grid(16));
  RuntimeLod lod(pm);
  std::vector<uint32_t> uploaded(lod.indices(), lod.indices() + 3 * lod.face_count());
  std::size_t uploaded_entries = 0, active_entries = 0;
  auto change = [&](std::size_t level) {
    const std::size_t before = lod.level();
    const RuntimeLod::IndexRange range = lod.set_level(level);
    uploaded.resize(3 * lod.face_count());
    ASSERT_LE(range.end, uploaded.size());
    if (lod.level() == before) {
      ASSERT_TRUE(range.empty());
    }
    if (!range.empty())
      std::copy(lod.indices() + range.begin, lod.indices() + range.end, uploaded.begin() + range.begin);
    ASSERT_TRUE(std::equal(uploaded.begin(), uploaded.end(), lod.indices())) << "level " << level;
    uploaded_entries += range.end - range.begin;
    active_entries += uploaded.size();
  };
  for (std::size_t level = 0; level <= lod.max_level(); ++level) change(level);
  for (std::size_t level = lod.max_level() + 1; level-- > 0;) change(level);
  // One split at a time, the ranges are less than whole uploads (64% here: one range spans
  // from the earliest corner a split moves, which may lie anywhere in the prefix).
  EXPECT_LT(uploaded_entries, active_entries);
  std::mt19937 random(3);
  std::uniform_int_distribution<std::size_t> any_level(0, lod.max_level());
  for (int jump = 0; jump < 200; ++jump) change(any_level(random));
  change(lod.level());  // no change: nothing to upload
}

TEST(Geomorph, EndsAreTheTwoLevelsExactlyAndEveryAlphaHasTheFineConnectivity) {
  const ProgressiveMesh pm = encode_ok(test::seamed_grid(16));
  RuntimeLod lod(pm);
  for (auto [a, b] : {std::pair<std::size_t, std::size_t>{0, pm.split_count()},
                      {pm.split_count() / 4, pm.split_count() / 2},
                      {10, 11},
                      {pm.split_count(), pm.split_count()}}) {
    SCOPED_TRACE("morph " + std::to_string(a) + " -> " + std::to_string(b));
    const RuntimeLod::Geomorph morph = lod.geomorph(a, b);
    EXPECT_EQ(lod.level(), b);
    // alpha = 1: level b exactly, with every attribute.
    EXPECT_TRUE(test::same_attributed_faces(extract_level(pm, b), morph.mesh(1.0f)));
    // alpha = 0: level a's faces, with b's extra faces flattened to nothing.
    EXPECT_TRUE(test::same_attributed_faces(extract_level(pm, a),
                                            test::without_flat_faces(morph.mesh(0.0f))));
    // Any alpha: b's connectivity, positions between the ends.
    const Mesh start = morph.mesh(0.0f), end = morph.mesh(1.0f);
    for (float alpha : {0.25f, 0.5f, 0.9f}) {
      const Mesh mid = morph.mesh(alpha);
      ASSERT_EQ(mid.triangles, end.triangles);
      for (std::size_t i = 0; i < mid.positions.size(); ++i) {
        const float lo = std::min(start.positions[i], end.positions[i]);
        const float hi = std::max(start.positions[i], end.positions[i]);
        ASSERT_TRUE(mid.positions[i] >= lo - 1e-6f && mid.positions[i] <= hi + 1e-6f) << i;
      }
    }
  }
}

// A binding stores a RuntimeLod and its geomorphs side by side, and may move the first:
// a geomorph shares the runtime's wedge arrays, so it outlives a move and the runtime itself
// (under the sanitizers, a geomorph that pointed into the runtime would read freed memory).
static_assert(std::is_nothrow_move_constructible_v<RuntimeLod>);
static_assert(std::is_nothrow_move_constructible_v<RuntimeLod::Geomorph>);

TEST(Geomorph, OutlivesAMoveAndTheDestructionOfItsRuntime) {
  const ProgressiveMesh pm = encode_ok(test::seamed_grid(16));
  auto lod = std::make_unique<RuntimeLod>(pm);
  const RuntimeLod::Geomorph morph = lod->geomorph(pm.split_count() / 4, pm.split_count() / 2);
  const std::size_t wedges = morph.wedge_count();
  // Per wedge: a position (3), a texture coordinate (2), a normal (3), a colour (3 here).
  ASSERT_EQ(pm.color_components, 3u);
  auto evaluate = [&](float alpha) {
    std::vector<float> values(11 * wedges);
    morph.evaluate(alpha, values.data(), values.data() + 3 * wedges, values.data() + 5 * wedges,
                   values.data() + 8 * wedges);
    return values;
  };
  const std::vector<float> before = evaluate(0.5f);
  const Mesh start = morph.mesh(0.0f), end = morph.mesh(1.0f);

  RuntimeLod moved(std::move(*lod));
  moved.set_level(0);  // the geomorph does not follow the runtime's level either
  EXPECT_TRUE(test::same_attributed_faces(extract_level(pm, 0), moved.to_mesh()));
  lod.reset();
  EXPECT_EQ(evaluate(0.5f), before);
  EXPECT_TRUE(test::same_attributed_faces(start, morph.mesh(0.0f)));
  EXPECT_TRUE(test::same_attributed_faces(end, morph.mesh(1.0f)));
  EXPECT_TRUE(test::same_attributed_faces(extract_level(pm, pm.split_count() / 2), morph.mesh(1.0f)));
}

// to_mesh() keeps the material libraries, as extract_level() does.
TEST(RuntimeLod, ToMeshKeepsTheMaterialLibraries) {
  Mesh grid = test::seamed_grid(6);
  grid.material_libraries = {"scene.mtl", "more.mtl"};
  const ProgressiveMesh pm = encode_ok(grid);
  RuntimeLod lod(pm);
  for (std::size_t level : {std::size_t{0}, pm.split_count()}) {
    lod.set_level(level);
    EXPECT_EQ(lod.to_mesh().material_libraries, grid.material_libraries);
    EXPECT_EQ(lod.material_libraries(), grid.material_libraries);
  }
}

TEST(Geomorph, OnARealMeshTheCoarseEndIsTheCoarseLevel) {
  PM_SKIP_IF_NO_SHARED();
  Mesh mesh;
  ASSERT_TRUE(read_mesh(test::shared_mesh_path("fandisk.obj"), mesh).ok());
  const ProgressiveMesh pm = encode_ok(mesh);
  RuntimeLod lod(pm);
  const std::size_t a = level_for_faces(pm, mesh.face_count() / 10);
  const std::size_t b = level_for_faces(pm, mesh.face_count() / 2);
  const RuntimeLod::Geomorph morph = lod.geomorph(a, b);
  EXPECT_TRUE(test::same_faces(extract_level(pm, a), test::without_flat_faces(morph.mesh(0.0f))));
  const Mesh fine = extract_level(pm, b);
  EXPECT_TRUE(test::same_faces(fine, morph.mesh(1.0f)));
  // Every alpha: level b's vertices and connectivity, so its topology.
  const test::TopologySummary expected = test::summarize_topology(fine);
  for (float alpha : {0.0f, 0.3f, 1.0f}) {
    const Mesh mid = morph.mesh(alpha);
    EXPECT_EQ(mid.vertex_count(), fine.vertex_count());
    const test::TopologySummary got = test::summarize_topology(mid);
    EXPECT_EQ(got.euler, expected.euler);
    EXPECT_EQ(got.boundary_loops, expected.boundary_loops);
    EXPECT_EQ(got.components, expected.components);
    EXPECT_EQ(got.edge_manifold, expected.edge_manifold);
  }
}

}  // namespace
}  // namespace pm

namespace pm {
namespace {

bool identical(const Mesh& a, const Mesh& b) {
  return a.positions == b.positions && a.triangles == b.triangles && a.colors == b.colors &&
         a.uvs == b.uvs && a.uv_indices == b.uv_indices && a.normals == b.normals &&
         a.normal_indices == b.normal_indices && a.face_materials == b.face_materials &&
         a.material_names == b.material_names && a.material_libraries == b.material_libraries;
}

TEST(ExtractLevels, OneWalkGivesWhatExtractLevelGivesForEachLevelCoarseToFine) {
  const ProgressiveMesh pm = encode_ok(test::seamed_grid(16));
  const std::size_t full = pm.split_count();
  std::vector<std::size_t> emitted;
  extract_levels(pm, {full, 0, full / 3, full / 3, full + 10, 7},
                 [&](std::size_t level, const Mesh& mesh) {
                   emitted.push_back(level);
                   EXPECT_TRUE(identical(mesh, extract_level(pm, level))) << "level " << level;
                 });
  EXPECT_EQ(emitted, (std::vector<std::size_t>{0, 7, full / 3, full}));
}

}  // namespace
}  // namespace pm
