// Every path that produces a Mesh for a level gives the same fields (issue 27): extract_level
// (the reference), RuntimeLod::to_mesh, RuntimeLod::Geomorph::mesh at alpha 1 (and at alpha
// 0, the coarse end), SelectiveRefinement::to_mesh with the splits of the level applied, and
// extract_level on what PmStreamReader decoded (mid-stream and finished).
//
// "The same" means, against extract_level's mesh of the level:
//  - the same faces, corner by corner: the multiset of faces, each with its three corners'
//    position, colour, texture coordinate and normal bits, and its material's name (vertex
//    and table numbering, face order and the corner a face starts at are free:
//    test::same_attributed_faces). RuntimeLod::to_mesh has one vertex per wedge, so its vertex
//    count is larger; corner by corner it is the same.
//  - the same material names and libraries, colour components and face count.
//  - the same vertex count for the paths with one vertex per vertex (SelectiveRefinement and
//    extract_level on the streamed mesh); a geomorph writes the vertices its faces use, so it
//    has them less the loose vertices of full detail.
//  - at alpha 0 a geomorph from level a to b is level a, plus faces of no area (b's faces
//    that a does not have, collapsed onto their ancestors): the same after those are dropped.
//    Its corners start at their wedge's ancestor (Hoppe 1996, §4.2: one per wedge), so their
//    attributes are level a's where each wedge of b has one ancestor wedge, as in every mesh
//    the encoder writes. The synthetic goldens give one new wedge to corners that had
//    different wedges before the split: there, positions alone are compared at alpha 0.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/lod_runtime.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "pm/selective_refinement.h"
#include "test_meshes.h"
#include "test_util.h"

namespace pm {
namespace {

::testing::AssertionResult same_fields(const Mesh& expected, const Mesh& actual,
                                       bool same_vertices) {
  if (expected.face_count() != actual.face_count())
    return ::testing::AssertionFailure()
           << expected.face_count() << " faces expected, " << actual.face_count() << " found";
  if (same_vertices && expected.vertex_count() != actual.vertex_count())
    return ::testing::AssertionFailure() << expected.vertex_count() << " vertices expected, "
                                         << actual.vertex_count() << " found";
  if (expected.color_components != actual.color_components)
    return ::testing::AssertionFailure() << "colour components differ";
  if (expected.material_names != actual.material_names)
    return ::testing::AssertionFailure() << "material names differ";
  if (expected.material_libraries != actual.material_libraries)
    return ::testing::AssertionFailure() << "material libraries differ";
  if (expected.has_uvs() != actual.has_uvs() || expected.has_normals() != actual.has_normals() ||
      expected.has_materials() != actual.has_materials())
    return ::testing::AssertionFailure() << "the kinds of attributes differ";
  return test::same_attributed_faces(expected, actual);
}

// Vertices some face uses.
std::size_t referenced_vertices(const Mesh& mesh) {
  std::vector<bool> used(mesh.vertex_count());
  for (uint32_t v : mesh.triangles) used[v] = true;
  return static_cast<std::size_t>(std::count(used.begin(), used.end(), true));
}

void check_every_path(const ProgressiveMesh& pm, const std::string& bytes,
                      bool attributes_at_start = true) {
  const std::size_t n = pm.split_count();
  std::vector<std::size_t> levels = {0, n / 4, n / 2, (3 * n) / 4, n};
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());

  RuntimeLod lod(pm);
  SelectiveRefinement selective(pm);
  // The streamed mesh: whole, and the prefix decoded when half the bytes have arrived.
  PmStreamReader reader;
  ASSERT_TRUE(reader.append(std::string_view(bytes).substr(0, bytes.size() / 2)).is_ok());
  const bool half_has_base = reader.has_base();  // a 1.x stream is decoded at finish()
  const ProgressiveMesh half = half_has_base ? reader.mesh() : ProgressiveMesh();
  ASSERT_TRUE(reader.append(std::string_view(bytes).substr(bytes.size() / 2)).is_ok());
  ASSERT_TRUE(reader.finish().is_ok());
  ProgressiveMesh streamed;
  ASSERT_TRUE(reader.take(streamed).is_ok());

  for (std::size_t level : levels) {
    SCOPED_TRACE("level " + std::to_string(level) + " of " + std::to_string(n));
    const Mesh expected = extract_level(pm, level);
    EXPECT_EQ(expected.vertex_count(), vertices_at_level(pm, level));
    EXPECT_EQ(expected.face_count(), faces_at_level(pm, level));

    lod.set_level(level);
    EXPECT_EQ(lod.face_count(), expected.face_count());
    EXPECT_EQ(lod.vertex_count(), expected.vertex_count());
    EXPECT_TRUE(same_fields(expected, lod.to_mesh(), false)) << "RuntimeLod::to_mesh";

    const RuntimeLod::Geomorph to_level = lod.geomorph(level / 2, level);
    const Mesh end = to_level.mesh(1.0f);
    EXPECT_TRUE(same_fields(expected, end, false)) << "Geomorph::mesh(1)";
    EXPECT_EQ(end.vertex_count(), referenced_vertices(expected));
    const RuntimeLod::Geomorph from_level = lod.geomorph(level, std::min(n, level + 1 + n / 8));
    const Mesh start = test::without_flat_faces(from_level.mesh(0.0f));
    if (attributes_at_start) {
      EXPECT_TRUE(same_fields(test::without_flat_faces(expected), start, false))
          << "Geomorph::mesh(0)";
    } else {
      EXPECT_TRUE(test::same_faces(test::without_flat_faces(expected), start))
          << "Geomorph::mesh(0)";
    }

    std::vector<bool> wanted(n, false);
    std::fill(wanted.begin(), wanted.begin() + level, true);
    selective.set_applied(wanted);
    ASSERT_EQ(selective.applied_count(), level);  // a prefix forces nothing
    EXPECT_TRUE(same_fields(expected, selective.to_mesh(), true)) << "SelectiveRefinement";

    EXPECT_TRUE(same_fields(expected, extract_level(streamed, level), true)) << "PmStreamReader";
    if (half_has_base && level <= half.split_count() && half.split_count() < n) {
      EXPECT_TRUE(same_fields(expected, extract_level(half, level), true))
          << "PmStreamReader mid-stream, " << half.split_count() << " splits decoded";
    }
  }
}

std::string write_small_chunks(const ProgressiveMesh& pm) {
  WriteOptions options;
  options.chunk_splits = 256;  // several chunks even on the samples
  std::string bytes;
  EXPECT_TRUE(test::ok(write_pm(pm, options, bytes)));
  return bytes;
}

class LevelPaths : public ::testing::TestWithParam<test::TestMesh> {};

TEST_P(LevelPaths, EveryPathGivesTheSameFieldsAtSeveralLevels) {
  PM_SKIP_IF_MISSING(GetParam());
  Mesh mesh;
  ASSERT_TRUE(test::ok(read_mesh(GetParam().path, mesh)));
  ProgressiveMesh pm;
  ASSERT_TRUE(test::ok(encode(mesh, EncodeOptions{}, pm)));
  check_every_path(pm, write_small_chunks(pm));
}

INSTANTIATE_TEST_SUITE_P(Meshes, LevelPaths, ::testing::ValuesIn(test::all_test_meshes()),
                         test::test_mesh_name);

// The goldens: every stream version, with welds, carried faces, loose vertices (attributed),
// the input's order (ordered), quantized and decimal positions.
TEST(LevelPaths, EveryPathGivesTheSameFieldsOnTheGoldens) {
  for (const char* name : {"attributed-v2.4.pm", "ordered-v2.4.pm", "small-v2.4.pm",
                           "generated-v2.4.pm", "textured-q12-v2.2.pm", "significant-v2.4.pm",
                           "attributed-v1.1.pm"}) {
    SCOPED_TRACE(name);
    const std::string bytes = test::read_file(std::string(PM_TEST_DATA_DIR) + "/golden/" + name);
    ProgressiveMesh pm;
    ASSERT_TRUE(test::ok(read_pm(bytes, pm)));
    check_every_path(pm, bytes, /*attributes_at_start=*/false);
  }
}

}  // namespace
}  // namespace pm
