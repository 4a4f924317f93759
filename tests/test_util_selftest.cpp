// Tests of the test helpers themselves (test_util.h), on small literal meshes whose
// answers can be counted by hand.
#include <cmath>
#include <limits>
#include <string>

#include "test_util.h"

namespace pm::test {
namespace {

pm::Mesh make_mesh(std::vector<float> positions, std::vector<uint32_t> triangles) {
  pm::Mesh mesh;
  mesh.positions = std::move(positions);
  mesh.triangles = std::move(triangles);
  return mesh;
}

pm::Mesh single_triangle() {
  return make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2});
}

// Unit tetrahedron, faces counter-clockwise seen from outside.
pm::Mesh tetrahedron() {
  return make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3});
}

// A unit cube's bottom and four sides (10 triangles), open at the top.
pm::Mesh open_cube() {
  // Vertex i is at (i & 1, (i >> 1) & 1, (i >> 2) & 1).
  std::vector<float> positions;
  for (int i = 0; i < 8; ++i) {
    positions.insert(positions.end(), {float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)});
  }
  return make_mesh(positions, {0, 2, 3, 0, 3, 1,    // bottom, z = 0, facing -z
                               0, 1, 5, 0, 5, 4,    // y = 0, facing -y
                               1, 3, 7, 1, 7, 5,    // x = 1, facing +x
                               3, 2, 6, 3, 6, 7,    // y = 1, facing +y
                               2, 0, 4, 2, 4, 6});  // x = 0, facing -x
}

// A 4 x 4 grid of vertices (3 x 3 cells) with the middle cell removed.
pm::Mesh square_annulus() {
  std::vector<float> positions;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) positions.insert(positions.end(), {float(i), float(j), 0.0f});
  }
  std::vector<uint32_t> triangles;
  for (uint32_t j = 0; j < 3; ++j) {
    for (uint32_t i = 0; i < 3; ++i) {
      if (i == 1 && j == 1) continue;
      const uint32_t v00 = 4 * j + i, v10 = v00 + 1, v01 = v00 + 4, v11 = v00 + 5;
      triangles.insert(triangles.end(), {v00, v10, v11, v00, v11, v01});
    }
  }
  return make_mesh(positions, triangles);
}

// ---------------------------------------------------------------------------------------
// summarize_topology

TEST(SummarizeTopology, SingleTriangle) {
  const TopologySummary s = summarize_topology(single_triangle());
  EXPECT_EQ(s.vertices, 3);
  EXPECT_EQ(s.edges, 3);
  EXPECT_EQ(s.faces, 1);
  EXPECT_EQ(s.euler, 1);
  EXPECT_EQ(s.boundary_loops, 1);
  EXPECT_EQ(s.components, 1);
  EXPECT_TRUE(s.edge_manifold);
  EXPECT_TRUE(s.vertex_manifold);
  EXPECT_EQ(s.zero_area_faces, 0);
  EXPECT_EQ(s.non_manifold_edges, 0);
  EXPECT_EQ(s.non_manifold_vertices, 0);
}

TEST(SummarizeTopology, ClosedTetrahedron) {
  const TopologySummary s = summarize_topology(tetrahedron());
  EXPECT_EQ(s.vertices, 4);
  EXPECT_EQ(s.edges, 6);
  EXPECT_EQ(s.faces, 4);
  EXPECT_EQ(s.euler, 2);
  EXPECT_EQ(s.boundary_loops, 0);
  EXPECT_EQ(s.components, 1);
  EXPECT_TRUE(s.edge_manifold);
  EXPECT_TRUE(s.vertex_manifold);
}

TEST(SummarizeTopology, OpenCubeHasOneLoop) {
  const TopologySummary s = summarize_topology(open_cube());
  EXPECT_EQ(s.vertices, 8);
  EXPECT_EQ(s.edges, 17);
  EXPECT_EQ(s.faces, 10);
  EXPECT_EQ(s.euler, 1);
  EXPECT_EQ(s.boundary_loops, 1);
  EXPECT_TRUE(s.edge_manifold);
  EXPECT_TRUE(s.vertex_manifold);
}

TEST(SummarizeTopology, SquareAnnulusHasTwoLoops) {
  const TopologySummary s = summarize_topology(square_annulus());
  EXPECT_EQ(s.vertices, 16);
  EXPECT_EQ(s.edges, 32);
  EXPECT_EQ(s.faces, 16);
  EXPECT_EQ(s.euler, 0);
  EXPECT_EQ(s.boundary_loops, 2);
  EXPECT_EQ(s.components, 1);
  EXPECT_TRUE(s.edge_manifold);
  EXPECT_TRUE(s.vertex_manifold);
}

TEST(SummarizeTopology, UnreferencedVerticesAreNotCounted) {
  pm::Mesh mesh = single_triangle();
  mesh.positions.insert(mesh.positions.begin(), {5, 5, 5});  // vertex 0, unused
  mesh.triangles = {1, 2, 3};
  const TopologySummary s = summarize_topology(mesh);
  EXPECT_EQ(s.vertices, 3);
  EXPECT_EQ(s.euler, 1);
}

TEST(SummarizeTopology, TetrahedraSharingOneVertexAreNotVertexManifold) {
  pm::Mesh mesh = tetrahedron();
  // A copy moved so that its vertex 0 lands on the first one's vertex 3, (0, 0, 1).
  for (uint32_t v = 1; v < 4; ++v) {
    mesh.positions.insert(mesh.positions.end(), {mesh.positions[3 * v], mesh.positions[3 * v + 1],
                                                 mesh.positions[3 * v + 2] + 1});
  }
  const uint32_t copy_of[4] = {3, 4, 5, 6};
  for (int c = 0; c < 12; ++c) mesh.triangles.push_back(copy_of[mesh.triangles[c]]);
  const TopologySummary s = summarize_topology(mesh);
  EXPECT_EQ(s.vertices, 7);
  EXPECT_EQ(s.edges, 12);
  EXPECT_EQ(s.faces, 8);
  EXPECT_EQ(s.euler, 3);
  EXPECT_EQ(s.components, 1);  // joined through the shared vertex
  EXPECT_TRUE(s.edge_manifold);
  EXPECT_FALSE(s.vertex_manifold);
  EXPECT_EQ(s.non_manifold_vertices, 1);
  EXPECT_EQ(s.boundary_loops, 0);
}

TEST(SummarizeTopology, ThreeTrianglesOnOneEdgeAreNotEdgeManifold) {
  const pm::Mesh mesh =
      make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1}, {0, 1, 2, 1, 0, 3, 0, 1, 4});
  const TopologySummary s = summarize_topology(mesh);
  EXPECT_EQ(s.edges, 7);
  EXPECT_FALSE(s.edge_manifold);
  EXPECT_EQ(s.non_manifold_edges, 1);
  EXPECT_TRUE(s.vertex_manifold);  // the three faces are connected through the edge
}

TEST(SummarizeTopology, SameOrientationOnSharedEdgeIsNotEdgeManifold) {
  // Both faces run 0 -> 1: the second is flipped relative to the first.
  const pm::Mesh mesh = make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0}, {0, 1, 2, 0, 1, 3});
  const TopologySummary s = summarize_topology(mesh);
  EXPECT_FALSE(s.edge_manifold);
  EXPECT_EQ(s.non_manifold_edges, 1);
  // The boundary half-edges 1->2, 2->0, 1->3, 3->0 leave vertex 1 twice: counted as
  // components of the boundary graph, which is one.
  EXPECT_EQ(s.boundary_loops, 1);
}

TEST(SummarizeTopology, OppositeOrientationOnSharedEdgeIsEdgeManifold) {
  const pm::Mesh mesh = make_mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0}, {0, 1, 2, 1, 0, 3});
  const TopologySummary s = summarize_topology(mesh);
  EXPECT_TRUE(s.edge_manifold);
  EXPECT_EQ(s.boundary_loops, 1);
}

TEST(SummarizeTopology, CountsZeroAreaFaces) {
  const pm::Mesh mesh = make_mesh({0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0},
                                  {0, 1, 3,    // a proper triangle
                                   0, 1, 2,    // collinear corners
                                   3, 3, 1,    // repeated index
                                   0, 3, 0});  // repeated index, another position
  EXPECT_EQ(summarize_topology(mesh).zero_area_faces, 3);
}

TEST(SummarizeTopology, TinyButNonZeroAreaIsNotZero) {
  // The cross product is ~1e-45 * 1: still not exactly zero in double.
  const float tiny = std::numeric_limits<float>::denorm_min();
  const pm::Mesh mesh = make_mesh({0, 0, 0, 1, 0, 0, 0, tiny, 0}, {0, 1, 2});
  EXPECT_EQ(summarize_topology(mesh).zero_area_faces, 0);
}

TEST(SummarizeTopology, CountsComponents) {
  pm::Mesh mesh = single_triangle();
  mesh.positions.insert(mesh.positions.end(), {5, 0, 0, 6, 0, 0, 5, 1, 0});
  mesh.triangles.insert(mesh.triangles.end(), {3, 4, 5});
  const TopologySummary s = summarize_topology(mesh);
  EXPECT_EQ(s.components, 2);
  EXPECT_EQ(s.boundary_loops, 2);
}

TEST(SummarizeTopology, EmptyMesh) {
  const TopologySummary s = summarize_topology(pm::Mesh{});
  EXPECT_EQ(s.vertices, 0);
  EXPECT_EQ(s.faces, 0);
  EXPECT_EQ(s.components, 0);
  EXPECT_EQ(s.boundary_loops, 0);
  EXPECT_TRUE(s.edge_manifold);
  EXPECT_TRUE(s.vertex_manifold);
}

TEST(SummarizeTopology, RejectsOutOfRangeIndex) {
  EXPECT_THROW(summarize_topology(make_mesh({0, 0, 0}, {0, 0, 1})), std::out_of_range);
}

// ---------------------------------------------------------------------------------------
// canonical_faces / same_faces

TEST(CanonicalFaces, RotatesSmallestCornerFirstAndSorts) {
  const pm::Mesh mesh = make_mesh({3, 0, 0, 1, 0, 0, 2, 0, 0, 0, 5, 5}, {0, 1, 2, 3, 2, 0});
  const std::vector<FacePositions> faces = canonical_faces(mesh);
  ASSERT_EQ(faces.size(), 2u);
  EXPECT_EQ(faces[0], (FacePositions{0, 5, 5, 2, 0, 0, 3, 0, 0}));
  EXPECT_EQ(faces[1], (FacePositions{1, 0, 0, 2, 0, 0, 3, 0, 0}));
}

TEST(SameFaces, AcceptsRotatedCorners) {
  const pm::Mesh expected = tetrahedron();
  pm::Mesh actual = expected;
  std::rotate(actual.triangles.begin(), actual.triangles.begin() + 1, actual.triangles.begin() + 3);
  EXPECT_TRUE(same_faces(expected, actual));
}

TEST(SameFaces, AcceptsReorderedFacesAndRenumberedVertices) {
  const pm::Mesh expected = tetrahedron();
  // Vertices in reverse order (plus an unused one), faces in reverse order.
  pm::Mesh actual;
  actual.positions = {9, 9, 9};
  for (int v = 3; v >= 0; --v) {
    for (int axis = 0; axis < 3; ++axis)
      actual.positions.push_back(expected.positions[3 * v + axis]);
  }
  for (int f = 3; f >= 0; --f) {
    for (int k = 0; k < 3; ++k) actual.triangles.push_back(4 - expected.triangles[3 * f + k]);
  }
  EXPECT_TRUE(same_faces(expected, actual));
}

TEST(SameFaces, RejectsReflectedFace) {
  const pm::Mesh expected = tetrahedron();
  pm::Mesh actual = expected;
  std::swap(actual.triangles[1], actual.triangles[2]);
  const ::testing::AssertionResult result = same_faces(expected, actual);
  EXPECT_FALSE(result);
  EXPECT_NE(std::string(result.message()).find("1 only in expected, 1 only in actual"),
            std::string::npos)
      << result.message();
}

TEST(SameFaces, RejectsOneUlpChange) {
  const pm::Mesh expected = tetrahedron();
  pm::Mesh actual = expected;
  actual.positions[3] = std::nextafter(actual.positions[3], 2.0f);
  EXPECT_FALSE(same_faces(expected, actual));
}

TEST(SameFaces, RejectsNegativeZeroForZero) {
  const pm::Mesh expected = single_triangle();
  pm::Mesh actual = expected;
  actual.positions[0] = -0.0f;
  EXPECT_FALSE(same_faces(expected, actual));
}

TEST(SameFaces, MatchesNaNWithSameBits) {
  pm::Mesh mesh = single_triangle();
  mesh.positions[0] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(same_faces(mesh, mesh));
}

TEST(SameFaces, RejectsDuplicatedFace) {
  const pm::Mesh expected = tetrahedron();
  pm::Mesh actual = expected;
  actual.triangles.insert(actual.triangles.end(), {0, 2, 1});
  const ::testing::AssertionResult result = same_faces(expected, actual);
  EXPECT_FALSE(result);
  EXPECT_NE(std::string(result.message()).find("expected has 4 faces, actual has 5"),
            std::string::npos)
      << result.message();
}

// ---------------------------------------------------------------------------------------
// run_command

TEST(RunCommand, CapturesOutputAndExitCode) {
  const CommandResult result = run_command({"/bin/sh", "-c", "echo hi; echo err >&2; exit 3"});
  EXPECT_EQ(result.exit_code, 3);
  EXPECT_EQ(result.out, "hi\n");
  EXPECT_EQ(result.err, "err\n");
}

TEST(RunCommand, ReportsKillingSignalAs128Plus) {
  EXPECT_EQ(run_command({"/bin/sh", "-c", "kill -KILL $$"}).exit_code, 128 + 9);
  EXPECT_EQ(run_command({"/bin/sh", "-c", "kill -TERM $$"}).exit_code, 128 + 15);
}

TEST(RunCommand, PassesArgumentsVerbatim) {
  // No shell in between: spaces, quotes and $ reach the program unchanged.
  const CommandResult result =
      run_command({"/bin/sh", "-c", "printf '%s|' \"$@\"", "sh", "a b", "'q'", "$HOME", ""});
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_EQ(result.out, "a b|'q'|$HOME||");
}

TEST(RunCommand, FeedsStdinAndDrainsLargeOutputsWithoutDeadlock) {
  // 4 MiB through stdin, echoed on both stdout and stderr: far more than a pipe holds.
  std::string data;
  for (int i = 0; data.size() < (4u << 20); ++i) data += std::to_string(i) + '\n';
  const CommandResult result = run_command({"/bin/sh", "-c", "tee /dev/stderr"}, data);
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_TRUE(result.out == data) << "stdout differs: " << result.out.size() << " bytes";
  EXPECT_TRUE(result.err == data) << "stderr differs: " << result.err.size() << " bytes";
}

TEST(RunCommand, SurvivesProgramNotReadingStdin) {
  const CommandResult result = run_command({"/bin/true"}, std::string(4u << 20, 'x'));
  EXPECT_EQ(result.exit_code, 0);
}

TEST(RunCommand, ReportsProgramThatCannotStart) {
  const CommandResult result = run_command({"/nonexistent/program"});
  EXPECT_EQ(result.exit_code, 127);
  EXPECT_NE(result.err.find("/nonexistent/program"), std::string::npos) << result.err;
}

// ---------------------------------------------------------------------------------------
// TempDir, files, OBJ oracle, mesh locations

TEST(TempDir, CreatesAndRemovesDirectory) {
  std::string path;
  {
    TempDir dir;
    path = dir.path();
    EXPECT_TRUE(file_exists(path));
    EXPECT_EQ(dir.file("a.bin"), path + "/a.bin");
    const std::string bytes("zero\0byte\r\n\xff", 12);
    write_file(dir.file("a.bin"), bytes);
    EXPECT_TRUE(file_exists(dir.file("a.bin")));
    EXPECT_EQ(read_file(dir.file("a.bin")), bytes);
    write_file(dir.file("empty"), "");
    EXPECT_EQ(read_file(dir.file("empty")), "");
  }
  EXPECT_FALSE(file_exists(path));
}

TEST(Files, ReadingMissingFileThrows) {
  TempDir dir;
  EXPECT_FALSE(file_exists(dir.file("missing")));
  EXPECT_THROW(read_file(dir.file("missing")), std::runtime_error);
  EXPECT_THROW(write_file(dir.file("no/such/dir"), "x"), std::runtime_error);
}

TEST(LoadSimpleObj, ReadsCornerFormsNegativeIndicesAndPolygons) {
  TempDir dir;
  write_file(dir.file("m.obj"),
             "# comment\r\n"
             "o thing\n"
             "v 0 0 0\n"
             "v 1 0 0\r\n"
             "v 1 1 0 0.5 0.5 0.5\n"  // trailing vertex colour, ignored
             "v 0 1 0\n"
             "vt 0 0\nvn 0 0 1\n"
             "f 1/1/1 2//1 3/1 4\n"  // a quad: fanned into (1 2 3) (1 3 4)
             "v 2 0 0\n"
             "f -4 -1 -3\n");
  const pm::Mesh mesh = load_simple_obj(dir.file("m.obj"));
  EXPECT_EQ(mesh.positions, (std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 2, 0, 0}));
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 1, 4, 2}));
}

TEST(LoadSimpleObj, RejectsBadInput) {
  TempDir dir;
  write_file(dir.file("range.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  EXPECT_THROW(load_simple_obj(dir.file("range.obj")), std::runtime_error);
  write_file(dir.file("zero.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  EXPECT_THROW(load_simple_obj(dir.file("zero.obj")), std::runtime_error);
  write_file(dir.file("two.obj"), "v 0 0 0\nv 1 0 0\nf 1 2\n");
  EXPECT_THROW(load_simple_obj(dir.file("two.obj")), std::runtime_error);
  write_file(dir.file("number.obj"), "v 0 zero 0\n");
  EXPECT_THROW(load_simple_obj(dir.file("number.obj")), std::runtime_error);
  EXPECT_THROW(load_simple_obj(dir.file("missing.obj")), std::runtime_error);
}

TEST(MeshLocations, SamplesAreListed) {
  const std::vector<std::string> paths = sample_mesh_paths();
  ASSERT_FALSE(paths.empty());
  EXPECT_TRUE(std::is_sorted(paths.begin(), paths.end()));
  for (const std::string& path : paths) {
    EXPECT_EQ(path.substr(path.size() - 4), ".obj");
    EXPECT_TRUE(file_exists(path)) << path;
  }
}

TEST(MeshLocations, SharedMeshesAreListedWhenPresent) {
  PM_SKIP_IF_NO_SHARED();
  const std::vector<std::string> names = shared_mesh_names();
  ASSERT_FALSE(names.empty());
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
  for (const std::string& name : names) {
    EXPECT_EQ(name.find('/'), std::string::npos) << name;
    EXPECT_TRUE(file_exists(shared_mesh_path(name))) << name;
  }
}

TEST(AttributedFaces, RotationsOfAFaceWithTwoEqualCornersCompareEqual) {
  // Corners A, A, B (two vertices at one position, as at a weld or a seam split) written
  // from each corner: one face whatever the start.
  pm::Mesh a, b, c;
  for (pm::Mesh* m : {&a, &b, &c}) m->positions = {0, 0, 0, 0, 0, 0, 1, 0, 0};
  a.triangles = {0, 1, 2};
  b.triangles = {1, 2, 0};
  c.triangles = {2, 0, 1};
  EXPECT_TRUE(same_attributed_faces(a, b));
  EXPECT_TRUE(same_attributed_faces(a, c));
  // A texture coordinate tells the two equal positions apart.
  for (pm::Mesh* m : {&a, &b}) m->uvs = {0, 0, 0.5f, 0, 1, 0};
  a.uv_indices = {0, 1, 2};
  b.uv_indices = {1, 2, 0};
  EXPECT_TRUE(same_attributed_faces(a, b));
  b.uv_indices = {0, 2, 1};
  EXPECT_FALSE(same_attributed_faces(a, b));
}

TEST(SignificantBits, CountTheMantissaUpToItsLastOne) {
  EXPECT_EQ(significant_bits(1.0f), 1);
  EXPECT_EQ(significant_bits(0.25f), 1);
  EXPECT_EQ(significant_bits(0.75f), 2);       // 1.1 (binary) / 2
  EXPECT_EQ(significant_bits(0.3125f), 3);     // 1.01 / 4
  EXPECT_EQ(significant_bits(1.0625f), 5);     // 1.0001
  EXPECT_EQ(significant_bits(1.0f + 0x1p-23f), 24);
}

}  // namespace
}  // namespace pm::test
