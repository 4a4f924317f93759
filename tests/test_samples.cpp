// The committed sample meshes (samples/*.obj): they are what pm_make_samples writes, and
// each has the topology its README row promises. Read with the test oracle
// (load_simple_obj), not the library's reader, so a reader bug cannot hide here.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "test_util.h"

namespace pm::test {
namespace {

const char* const kSampleNames[] = {"block_features.obj", "nonmanifold.obj",   "polygons.obj",
                                    "sphere.obj",         "terrain_holes.obj", "textured.obj"};
// Written by the generator too, but not meshes.
const char* const kOtherSampleFiles[] = {"textured.mtl"};

std::string base_name(const std::string& path) {
  return path.substr(path.rfind('/') + 1);
}

// Where two texts first differ, by line, for a readable failure message.
std::string first_difference(const std::string& expected, const std::string& actual) {
  std::istringstream want(expected), got(actual);
  std::string want_line, got_line;
  for (int line = 1;; ++line) {
    const bool has_want = static_cast<bool>(std::getline(want, want_line));
    const bool has_got = static_cast<bool>(std::getline(got, got_line));
    if (!has_want && !has_got) return "same lines, different bytes (line endings?)";
    if (!has_want || !has_got || want_line != got_line) {
      return "line " + std::to_string(line) + ": committed '" + (has_want ? want_line : "<end>") +
             "', generated '" + (has_got ? got_line : "<end>") + "'";
    }
  }
}

// Six times the signed volume enclosed by the faces: positive when a closed mesh's faces
// are counter-clockwise seen from outside.
double six_times_volume(const pm::Mesh& mesh) {
  double sum = 0;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const float* a = &mesh.positions[3 * mesh.triangles[3 * f]];
    const float* b = &mesh.positions[3 * mesh.triangles[3 * f + 1]];
    const float* c = &mesh.positions[3 * mesh.triangles[3 * f + 2]];
    sum += double{a[0]} * (double{b[1]} * c[2] - double{b[2]} * c[1]) -
           double{a[1]} * (double{b[0]} * c[2] - double{b[2]} * c[0]) +
           double{a[2]} * (double{b[0]} * c[1] - double{b[1]} * c[0]);
  }
  return sum;
}

long faces_with_repeated_index(const pm::Mesh& mesh) {
  long count = 0;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const uint32_t* v = &mesh.triangles[3 * f];
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) ++count;
  }
  return count;
}

TEST(Samples, GeneratorReproducesCommittedFiles) {
  TempDir dir;
  const CommandResult run = run_command({PM_MAKE_SAMPLES_PATH, dir.path()});
  ASSERT_EQ(run.exit_code, 0) << run.err;

  std::vector<std::string> committed;
  for (const std::string& path : sample_mesh_paths()) committed.push_back(base_name(path));
  EXPECT_EQ(committed, std::vector<std::string>(std::begin(kSampleNames), std::end(kSampleNames)))
      << "samples/*.obj should be exactly what pm_make_samples writes";

  std::vector<const char*> files(std::begin(kSampleNames), std::end(kSampleNames));
  files.insert(files.end(), std::begin(kOtherSampleFiles), std::end(kOtherSampleFiles));
  for (const char* name : files) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(file_exists(dir.file(name)));
    const std::string generated = read_file(dir.file(name));
    const std::string expected = read_file(sample_mesh_path(name));
    EXPECT_TRUE(generated == expected)
        << "samples/" << name << " is stale or was edited by hand; regenerate it (see "
        << "samples/README.md). First difference: " << first_difference(expected, generated);
  }
}

TEST(Samples, GeneratorRejectsMissingArgument) {
  EXPECT_EQ(run_command({PM_MAKE_SAMPLES_PATH}).exit_code, 2);
}

TEST(Samples, SphereIsClosedBumpyGenusZero) {
  const pm::Mesh mesh = load_simple_obj(sample_mesh_path("sphere.obj"));
  const TopologySummary s = summarize_topology(mesh);
  EXPECT_EQ(s.faces, 5120);
  EXPECT_EQ(s.vertices, 2562);
  EXPECT_EQ(s.euler, 2);
  EXPECT_EQ(s.boundary_loops, 0);
  EXPECT_EQ(s.components, 1);
  EXPECT_TRUE(s.edge_manifold);
  EXPECT_TRUE(s.vertex_manifold);
  EXPECT_EQ(s.zero_area_faces, 0);
  EXPECT_GT(six_times_volume(mesh), 0) << "faces should be counter-clockwise seen from outside";
  // Bumpy, not round: the radius varies by well over a tessellation's worth.
  double min_radius = 10, max_radius = 0;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const float* p = &mesh.positions[3 * v];
    const double radius =
        std::sqrt(double{p[0]} * p[0] + double{p[1]} * p[1] + double{p[2]} * p[2]);
    min_radius = std::min(min_radius, radius);
    max_radius = std::max(max_radius, radius);
  }
  EXPECT_GT(max_radius - min_radius, 0.1);
  EXPECT_LT(max_radius - min_radius, 0.3);
}

TEST(Samples, TerrainHasFourBoundaryLoops) {
  const pm::Mesh mesh = load_simple_obj(sample_mesh_path("terrain_holes.obj"));
  const TopologySummary s = summarize_topology(mesh);
  EXPECT_EQ(s.boundary_loops, 4);  // the outer rim and three holes
  EXPECT_EQ(s.euler, -2);          // a disk with three holes
  EXPECT_EQ(s.components, 1);
  EXPECT_TRUE(s.edge_manifold);
  EXPECT_TRUE(s.vertex_manifold);
  EXPECT_EQ(s.zero_area_faces, 0);
  EXPECT_EQ(s.vertices, static_cast<long>(mesh.vertex_count())) << "no unreferenced vertices";
}

TEST(Samples, BlockIsClosedGenusZeroWithExpectedVolume) {
  const pm::Mesh mesh = load_simple_obj(sample_mesh_path("block_features.obj"));
  const TopologySummary s = summarize_topology(mesh);
  EXPECT_EQ(s.euler, 2);
  EXPECT_EQ(s.boundary_loops, 0);
  EXPECT_EQ(s.components, 1);
  EXPECT_TRUE(s.edge_manifold);
  EXPECT_TRUE(s.vertex_manifold);
  EXPECT_EQ(s.zero_area_faces, 0);
  // Profile area 24*8 + 12*8 - 4*4/2 = 280 lattice units, depth 12, lattice step 1/8.
  EXPECT_DOUBLE_EQ(six_times_volume(mesh) / 6, 280.0 * 12 / 512);
}

TEST(Samples, NonManifoldHasEachDefect) {
  const pm::Mesh mesh = load_simple_obj(sample_mesh_path("nonmanifold.obj"));
  const TopologySummary s = summarize_topology(mesh);
  EXPECT_FALSE(s.edge_manifold);
  EXPECT_FALSE(s.vertex_manifold);
  EXPECT_EQ(s.non_manifold_vertices, 1);  // the pyramids' shared tip
  EXPECT_EQ(faces_with_repeated_index(mesh), 1);
  EXPECT_EQ(s.zero_area_faces, 1);  // that one; nothing else is degenerate
  EXPECT_EQ(static_cast<long>(mesh.vertex_count()) - s.vertices, 2) << "unreferenced vertices";
  EXPECT_EQ(s.components, 4);  // boxes sharing an edge, pyramids, box with fin, sheet

  // Exactly one face appears twice (same corners, same orientation).
  const std::vector<FacePositions> faces = canonical_faces(mesh);
  long repeats = 0;
  for (std::size_t i = 1; i < faces.size(); ++i) repeats += faces[i] == faces[i - 1];
  EXPECT_EQ(repeats, 1);
}

TEST(Samples, PolygonsTriangulateToTwoPieces) {
  const pm::Mesh mesh = load_simple_obj(sample_mesh_path("polygons.obj"));
  const TopologySummary s = summarize_topology(mesh);
  EXPECT_EQ(s.vertices, 14);
  EXPECT_EQ(s.faces, 18);  // 2 pentagons -> 6, 6 quads -> 12
  EXPECT_EQ(s.components, 2);
  EXPECT_EQ(s.boundary_loops, 1);  // the sign; the house is closed
  EXPECT_EQ(s.euler, 3);           // closed house 2 + open sign 1
  EXPECT_TRUE(s.edge_manifold);
  EXPECT_TRUE(s.vertex_manifold);
  EXPECT_EQ(s.zero_area_faces, 0);
}

// The oracle reads positions and faces only; the attributes are checked here by counting
// statements, and through the library's reader in test_attribute_io.cpp.
TEST(Samples, TexturedIsAClosedVaseWithEveryAttribute) {
  const std::string path = sample_mesh_path("textured.obj");
  const pm::Mesh mesh = load_simple_obj(path);
  const TopologySummary s = summarize_topology(mesh);
  EXPECT_EQ(s.faces, 3712);
  EXPECT_EQ(s.vertices, 1858);
  EXPECT_EQ(s.euler, 2);
  EXPECT_EQ(s.boundary_loops, 0);
  EXPECT_EQ(s.components, 1);
  EXPECT_TRUE(s.edge_manifold);
  EXPECT_TRUE(s.vertex_manifold);
  EXPECT_EQ(s.zero_area_faces, 0);
  EXPECT_GT(six_times_volume(mesh), 0) << "faces should be counter-clockwise seen from outside";

  std::istringstream text(read_file(path));
  std::string line;
  long coloured_vertices = 0, uvs = 0, normals = 0, full_corners = 0;
  std::vector<std::string> materials, libraries;
  while (std::getline(text, line)) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    std::vector<std::string> rest;
    for (std::string word; words >> word;) rest.push_back(word);
    if (keyword == "v" && rest.size() == 6) ++coloured_vertices;
    if (keyword == "vt") ++uvs;
    if (keyword == "vn") ++normals;
    if (keyword == "usemtl") materials.push_back(rest.at(0));
    if (keyword == "mtllib") libraries = rest;
    if (keyword == "f") {
      for (const std::string& corner : rest) {
        full_corners += std::count(corner.begin(), corner.end(), '/') == 2 &&
                        corner.find("//") == std::string::npos;
      }
    }
  }
  EXPECT_EQ(coloured_vertices, 1858);
  // More texture coordinates than vertices (seams) and normals (hard edges at the rims).
  EXPECT_EQ(uvs, 25 * 65 + 2 * (3 * 64 + 1));
  EXPECT_EQ(normals, 25 * 64 + 2);
  EXPECT_EQ(full_corners, 3 * 3712) << "every corner is v/vt/vn";
  EXPECT_EQ(materials, (std::vector<std::string>{"body", "caps"}));
  EXPECT_EQ(libraries, (std::vector<std::string>{"textured.mtl"}));
  const std::string library = read_file(sample_mesh_path("textured.mtl"));
  EXPECT_NE(library.find("newmtl body\n"), std::string::npos);
  EXPECT_NE(library.find("newmtl caps\n"), std::string::npos);
}

}  // namespace
}  // namespace pm::test
