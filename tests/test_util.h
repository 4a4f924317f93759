// Shared helpers for the pm test suite: independent topology checks, exact face-set
// comparison, test mesh locations, subprocess runs, temporary directories and file IO.
//
// Everything here is deliberately independent of the library under test (no pm::read_mesh,
// no OpenMesh), so that it can serve as an oracle for it.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <ostream>
#include <string>
#include <vector>

#include "pm/mesh.h"
#include "pm/status.h"

namespace pm::test {

// ---------------------------------------------------------------------------------------
// Topology
// ---------------------------------------------------------------------------------------

// Counts computed directly on Mesh::triangles (the index list), with these definitions:
//
//  * vertices: distinct vertex indices referenced by some face (unreferenced vertices in
//    Mesh::positions are not counted).
//  * edges: distinct undirected edges {a, b} with a != b among the faces' three sides. A
//    face with a repeated index (a, a, b) contributes its sides a-b and b-a (one undirected
//    edge used twice, in opposite directions) and no a-a edge.
//  * faces: Mesh::face_count(), degenerate faces included.
//  * euler: vertices - edges + faces.
//  * boundary edges: undirected edges used by exactly one face side.
//  * boundary_loops: if every vertex on the boundary has exactly one outgoing and one
//    incoming boundary half-edge (the manifold case), the number of cycles found by walking
//    the directed boundary half-edges. Otherwise (a boundary vertex is pinched,
//    neighbouring faces are inconsistently oriented, or the boundary is an open chain ending
//    at a non-manifold edge, which is not a boundary edge), the number of connected
//    components of the undirected boundary-edge graph; e.g. a figure-eight boundary counts
//    as 1 loop, and so does a fin's chain of free edges.
//  * components: connected components of faces, two faces being connected when they share
//    a vertex (so a pinched vertex joins its two sheets into one component).
//  * edge_manifold: every edge has at most 2 face sides, and when it has exactly 2 they run
//    in opposite directions (consistent orientation). non_manifold_edges counts the edges
//    breaking this (3+ faces, or 2 faces with the same direction, e.g. a duplicated face).
//  * vertex_manifold: around each referenced vertex v, the faces containing v form a single
//    fan: they are connected through edges incident to v. non_manifold_vertices counts the
//    vertices with 2+ fans (pinched vertices, e.g. two cones tip to tip). Only fan
//    connectivity is checked: a vertex on a complex (3+ face) edge has its faces connected
//    through that edge, so it is reported through edge_manifold, not here.
//  * zero_area_faces: faces with a repeated index, or whose corners' float positions give
//    a cross product (p1 - p0) x (p2 - p0), computed in double, of length exactly 0.
//
// Throws std::out_of_range if a face references a vertex beyond Mesh::positions.
struct TopologySummary {
  long vertices = 0;
  long edges = 0;
  long faces = 0;
  long euler = 0;
  int boundary_loops = 0;
  int components = 0;
  bool edge_manifold = true;
  bool vertex_manifold = true;
  long zero_area_faces = 0;
  long non_manifold_edges = 0;
  long non_manifold_vertices = 0;
};

TopologySummary summarize_topology(const pm::Mesh& mesh);

// Field-by-field, so that whole summaries can be compared: EXPECT_EQ(summary, expected).
bool operator==(const TopologySummary& a, const TopologySummary& b);
inline bool operator!=(const TopologySummary& a, const TopologySummary& b) {
  return !(a == b);
}

// One line with every field, e.g. "V=3 E=3 F=1 euler=1 loops=1 ...".
std::string to_string(const TopologySummary& summary);
// So that GoogleTest prints summaries readably in failure messages.
void PrintTo(const TopologySummary& summary, std::ostream* out);

// What every level of detail shares with its input: Euler characteristic, boundary loops,
// components, edge and vertex manifoldness and the non-manifold counts; and no more
// zero-area faces. The failure message gives both summaries.
::testing::AssertionResult keeps_topology(const TopologySummary& input, const TopologySummary& level);

// The mesh without the faces two of whose corners share a position (what a geomorph's start
// flattens), with their attributes and materials.
pm::Mesh without_flat_faces(const pm::Mesh& mesh);

// ---------------------------------------------------------------------------------------
// Exact face-set comparison
// ---------------------------------------------------------------------------------------

// A face as its three corner positions x0 y0 z0 x1 y1 z1 x2 y2 z2.
using FacePositions = std::array<float, 9>;

// Each face of the mesh by its corner positions (vertex indices do not matter), rotated so
// the lexicographically smallest corner comes first (rotation only, never reflection, so
// orientation is kept; ties between equal corners are broken by the following corners),
// then the whole list sorted. Two meshes describe the same faces, whatever their vertex
// numbering, face order or the corner each face starts at, iff these lists are equal.
// Ordering uses the IEEE total order on the float bits (-0 < +0, NaNs at the ends), so
// the result is well defined for any bit pattern.
// Throws std::out_of_range if a face references a vertex beyond Mesh::positions.
std::vector<FacePositions> canonical_faces(const pm::Mesh& mesh);

// A Status as an assertion: on failure, its code's name and its message.
// Usage: EXPECT_TRUE(pm::test::ok(validate(pm)));
::testing::AssertionResult ok(const pm::Status& status);

// Whether the two meshes have the same multiset of faces, comparing positions bit for bit
// (-0.0 differs from 0.0; a NaN equals a NaN with the same bits). Unreferenced vertices
// are ignored. On failure the message gives both face counts, how many faces are only in
// one side, and the first such face of each side, with exact values and bits.
// Usage: EXPECT_TRUE(pm::test::same_faces(expected, actual));
::testing::AssertionResult same_faces(const pm::Mesh& expected, const pm::Mesh& actual);

// A face with everything its corners carry: per corner the bits of its position, colour,
// texture coordinate and normal (0xFFFFFFFF for a missing one), rotated so the smallest
// corner comes first; and its material's name ("" for none).
struct AttributedFace {
  std::array<std::vector<uint32_t>, 3> corners;
  std::string material;
  bool operator<(const AttributedFace& o) const;
  bool operator==(const AttributedFace& o) const;
};
// The faces of the mesh, sorted: two meshes have the same faces and corner attributes, bit
// for bit, iff these lists are equal, whatever their vertex and value numbering, face
// order and the corner each face starts at.
std::vector<AttributedFace> attributed_faces(const pm::Mesh& mesh);
// Like same_faces(), with every corner attribute; the message names the first difference.
::testing::AssertionResult same_attributed_faces(const pm::Mesh& expected, const pm::Mesh& actual);

// ---------------------------------------------------------------------------------------
// Test meshes
// ---------------------------------------------------------------------------------------

// A bumpy n x n grid over [0, 1]^2 (n even) with three kinds of discontinuity crossing it:
// a UV seam along x = 0.5 (two charts), a normal crease along y = 0.5, a material border
// along the diagonal x = y (which the triangles' diagonals follow), and a colour per
// vertex, (x, y, 0.5).
pm::Mesh seamed_grid(int n);

// PM_SHARED_MESHES_DIR + "/" + name, e.g. shared_mesh_path("cow.obj").
std::string shared_mesh_path(const std::string& name);
// Whether PM_SHARED_MESHES_DIR (../shared/meshes, outside the repository) exists.
bool shared_meshes_available();
// File names (not paths) of the .obj/.off/.ply files in PM_SHARED_MESHES_DIR, sorted;
// empty if the folder is absent.
std::vector<std::string> shared_mesh_names();
// Full paths of samples/*.obj (the committed samples, PM_SAMPLES_DIR), sorted.
std::vector<std::string> sample_mesh_paths();
// PM_SAMPLES_DIR + "/" + name, e.g. sample_mesh_path("sphere.obj").
std::string sample_mesh_path(const std::string& name);

// The message given when the real meshes are absent; also printed on stderr, so that a
// run silently skipping them is noticed.
inline constexpr const char kNoSharedMeshesMessage[] =
    "../shared/meshes not found: skipping tests on real meshes";
// Prints kNoSharedMeshesMessage on stderr (once per process); used by the macro below.
void warn_no_shared_meshes();

// Put first in a test that needs the real meshes: skips the test (GTEST_SKIP returns from
// the test body) with a loud message when ../shared/meshes is absent.
#define PM_SKIP_IF_NO_SHARED()                            \
  do {                                                    \
    if (!::pm::test::shared_meshes_available()) {         \
      ::pm::test::warn_no_shared_meshes();                \
      GTEST_SKIP() << ::pm::test::kNoSharedMeshesMessage; \
    }                                                     \
  } while (false)

// A minimal OBJ reader, independent of the library's, used as an oracle: reads only `v`
// (first three numbers) and `f` lines; face corners may be `v`, `v/vt`, `v//vn` or
// `v/vt/vn` (only v is used), 1-based or negative (relative to the vertices read so far).
// Polygons are split into a fan from their first corner: (c0 c1 c2), (c0 c2 c3), ...
// Every other line is ignored. Throws std::runtime_error ("path:line: reason") on an
// unreadable file, a malformed number, an out-of-range index or a face of < 3 corners.
pm::Mesh load_simple_obj(const std::string& path);

// ---------------------------------------------------------------------------------------
// Subprocesses, files, temporary directories
// ---------------------------------------------------------------------------------------

struct CommandResult {
  int exit_code = -1;  // exit status, or 128 + signal number if killed by a signal
  std::string out;     // everything the program wrote on stdout
  std::string err;     // everything the program wrote on stderr
};

// Runs argv[0] (looked up in PATH if it has no '/') with the given arguments, no shell
// involved, feeding stdin_data on its stdin and then closing it. stdout and stderr are
// captured in full, concurrently (poll), so a chatty program cannot deadlock on a full
// pipe. If the program cannot be started, exit_code is 127 and err says why. Waits for the
// program to exit (and for anything holding its stdout/stderr open to close them).
// Throws std::invalid_argument on an empty argv, std::runtime_error if pipe/fork fails.
CommandResult run_command(const std::vector<std::string>& argv, const std::string& stdin_data = "");

// A fresh directory (mkdtemp under $TMPDIR, or /tmp), removed with all its contents when
// the object is destroyed. Not copyable. Throws std::runtime_error if creation fails.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::string& path() const { return path_; }
  // path() + "/" + name; the file is not created.
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

// Whole-file binary IO; both throw std::runtime_error naming the path on failure.
std::string read_file(const std::string& path);
void write_file(const std::string& path, const std::string& bytes);
// Whether path names an existing file (or directory).
bool file_exists(const std::string& path);

// The significant bits of a normal float: 24 less the trailing zeros of its stored mantissa
// (1 for a power of two).
inline int significant_bits(float x) {
  uint32_t b = 0;
  std::memcpy(&b, &x, sizeof b);
  const uint32_t mantissa = b & 0x7FFFFFu;
  return mantissa == 0 ? 1 : 24 - __builtin_ctz(mantissa);
}

}  // namespace pm::test
