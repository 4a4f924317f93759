// The encoder's acceptance on real meshes, in-process: lossless at full detail, topology
// kept at every level, face counts honoured, features kept, a small base mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <set>
#include <string>
#include <tuple>

#include "simplify/manifold_repair.h"
#include "simplify/simplifier.h"
#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "pm/surface_distance.h"
#include "test_meshes.h"
#include "test_util.h"
#include "simplify/vertex_classification.h"

namespace pm {
namespace {

using test::TestMesh;

struct Encoded {
  Mesh input;
  ProgressiveMesh pm;
};

// Reads, encodes, and round-trips through the .pm codec, as pmenc | pmdec would.
Encoded encode_file(const std::string& path, const EncodeOptions& options = {}) {
  Encoded e;
  Status s = read_mesh(path, e.input);
  EXPECT_TRUE(s.is_ok()) << path << ": " << s.message();
  ProgressiveMesh direct;
  s = encode(e.input, options, direct);
  EXPECT_TRUE(s.is_ok()) << path << ": " << s.message();
  std::string bytes;
  s = write_pm(direct, WriteOptions{}, bytes);
  EXPECT_TRUE(s.is_ok()) << s.message();
  s = read_pm(bytes, e.pm);
  EXPECT_TRUE(s.is_ok()) << s.message();
  return e;
}

// The collapse loop (one since issue 25, the former fast loop: the names keep "fast") with
// either metric, with one heap or in regions at once (forced here on every mesh; by default
// on meshes of 16384 vertices or more).
enum class Loop { kFast, kFastRegions, kFastSchroeder, kFastSchroederRegions };

// Every acceptance property holds for every loop.
class EveryMesh : public ::testing::TestWithParam<std::tuple<TestMesh, Loop>> {
 protected:
  const TestMesh& mesh() const { return std::get<0>(GetParam()); }
  EncodeOptions options() const {
    EncodeOptions o;
    const Loop loop = std::get<1>(GetParam());
    const bool regions = loop == Loop::kFastRegions || loop == Loop::kFastSchroederRegions;
    o.metric = loop == Loop::kFastSchroeder || loop == Loop::kFastSchroederRegions
                   ? Metric::kSchroeder
                   : Metric::kQuadric;
    o.fast_partition_vertices = regions ? 1 : 0;
    return o;
  }
  Encoded encoded() const {
    const EncodeOptions o = options();
    Encoded e = encode_file(mesh().path, o);
    return e;
  }
};

std::string every_mesh_name(const ::testing::TestParamInfo<std::tuple<TestMesh, Loop>>& info) {
  const Loop loop = std::get<1>(info.param);
  return std::get<0>(info.param).name + (loop == Loop::kFast                 ? "_fast"
                                         : loop == Loop::kFastRegions          ? "_fast_regions"
                                         : loop == Loop::kFastSchroeder        ? "_fast_schroeder"
                                                                               : "_fast_schroeder_regions");
}

TEST_P(EveryMesh, FullDetailIsTheInputExactly) {
  PM_SKIP_IF_MISSING(mesh());
  const Encoded e = encoded();
  const Mesh full = extract_level(e.pm, e.pm.split_count());
  EXPECT_TRUE(test::same_faces(e.input, full));
  // Every corner's colour, texture coordinate and normal, and every face's material, too.
  if (!options().drop_attributes) {
    EXPECT_TRUE(test::same_attributed_faces(e.input, full));
  }
  EXPECT_EQ(full.vertex_count(), e.input.vertex_count());
  EXPECT_EQ(full.face_count(), e.input.face_count());
  EXPECT_EQ(faces_at_level(e.pm, e.pm.split_count()), e.input.face_count());
  EXPECT_EQ(vertices_at_level(e.pm, e.pm.split_count()), e.input.vertex_count());
}

TEST_P(EveryMesh, EveryLevelKeepsTheInputTopology) {
  PM_SKIP_IF_MISSING(mesh());
  const Encoded e = encoded();
  const test::TopologySummary in = test::summarize_topology(e.input);
  const std::size_t n = e.pm.split_count();
  ASSERT_GT(n, 0u);
  constexpr int kLevels = 12;
  for (int i = 0; i <= kLevels; ++i) {
    const std::size_t level = n * i / kLevels;
    const Mesh lod = extract_level(e.pm, level);
    const test::TopologySummary out = test::summarize_topology(lod);
    SCOPED_TRACE("level " + std::to_string(level) + " of " + std::to_string(n));
    // Collapses never make a degenerate face; the input's own stay.
    EXPECT_TRUE(test::keeps_topology(in, out));
    EXPECT_EQ(lod.face_count(), faces_at_level(e.pm, level));
    EXPECT_EQ(lod.vertex_count(), vertices_at_level(e.pm, level));
  }
}

TEST_P(EveryMesh, FaceRequestsGiveNOrNPlusOne) {
  PM_SKIP_IF_MISSING(mesh());
  const Encoded e = encoded();
  const std::size_t base = faces_at_level(e.pm, 0);
  const std::size_t full = faces_at_level(e.pm, e.pm.split_count());
  // Every N on small meshes; a dense spread of N on large ones.
  const std::size_t step = std::max<std::size_t>(1, (full - base) / 3000);
  for (std::size_t n = base; n <= full; n += step) {
    const std::size_t got = faces_at_level(e.pm, level_for_faces(e.pm, n));
    ASSERT_TRUE(got == n || got == n + 1) << "requested " << n << " faces, got " << got;
  }
  // Every N: the face counts of consecutive levels step by 1 or 2, so the first level
  // reaching N has N or N + 1 faces.
  std::size_t level = 0, faces = base;
  for (std::size_t n = base; n <= full; ++n) {
    while (faces < n) faces += e.pm.splits[level++].new_face_count();
    ASSERT_TRUE(faces == n || faces == n + 1)
        << "level " << level << " has " << faces << " for " << n;
  }
  EXPECT_EQ(faces_at_level(e.pm, level_for_faces(e.pm, full)), full);
  EXPECT_EQ(level_for_faces(e.pm, full + 100), e.pm.split_count());
  EXPECT_EQ(level_for_faces(e.pm, 0), 0u);
}

TEST_P(EveryMesh, ErrorBoundsAreNonIncreasingAndSelectLevels) {
  PM_SKIP_IF_MISSING(mesh());
  const Encoded e = encoded();
  for (std::size_t i = 1; i < e.pm.split_count(); ++i)
    ASSERT_LE(e.pm.splits[i].error, e.pm.splits[i - 1].error) << "split " << i;
  EXPECT_EQ(error_at_level(e.pm, e.pm.split_count()), 0.0f);
  if (e.pm.split_count() == 0) return;
  const float mid = e.pm.splits[e.pm.split_count() / 2].error;
  const std::size_t level = level_for_error(e.pm, mid);
  EXPECT_LE(error_at_level(e.pm, level), mid);
  if (level > 0) {
    EXPECT_GT(error_at_level(e.pm, level - 1), mid);
  }
  EXPECT_EQ(
      level_for_error(e.pm, 0.0), e.pm.split_count() - [&] {
        std::size_t zero = 0;  // trailing splits of zero error (flat regions) are not needed
        while (zero < e.pm.split_count() && e.pm.splits[e.pm.split_count() - 1 - zero].error == 0)
          ++zero;
        return zero;
      }());
}

INSTANTIATE_TEST_SUITE_P(Meshes, EveryMesh,
                         ::testing::Combine(::testing::ValuesIn(test::all_test_meshes()),
                                            ::testing::Values(Loop::kFast, Loop::kFastRegions,
                                                              Loop::kFastSchroeder,
                                                              Loop::kFastSchroederRegions)),
                         every_mesh_name);

// The quadric metric, the default, must stay closer to the input than Schroeder's criteria
// (measured, Metro-style) on the samples with curvature and features: its RMS distance
// summed over the 10% and 2% levels is no larger. On the bumpy sphere the two metrics are
// equal within a few per cent, either may win by level (quadric/Schroeder RMS at 36 levels
// from 1.5% to 12% of the faces: 0.96 to 1.09, quadric no larger at 15 of them with the
// former default loop, 0.96 to 1.08 and 18 of 36 with the one loop), so there the quadric's
// sum may be up to 3% larger (the one loop: 1.018; the former default loop: 0.998).
TEST(Quality, QuadricIsCloserThanSchroederOnTheSamples) {
  for (const char* name : {"sphere.obj", "block_features.obj", "terrain_holes.obj"}) {
    EncodeOptions schroeder, quadric;
    schroeder.metric = Metric::kSchroeder;
    quadric.metric = Metric::kQuadric;
    const Encoded s = encode_file(test::sample_mesh_path(name), schroeder);
    const Encoded q = encode_file(test::sample_mesh_path(name), quadric);
    double schroeder_sum = 0, quadric_sum = 0;
    for (double ratio : {0.1, 0.02}) {
      const std::size_t faces = static_cast<std::size_t>(ratio * s.input.face_count());
      SurfaceDistance ds, dq;
      ASSERT_TRUE(measure_surface_distance(s.input,
                                           extract_level(s.pm, level_for_faces(s.pm, faces)),
                                           DistanceOptions{}, ds)
                      .is_ok());
      ASSERT_TRUE(measure_surface_distance(q.input,
                                           extract_level(q.pm, level_for_faces(q.pm, faces)),
                                           DistanceOptions{}, dq)
                      .is_ok());
      schroeder_sum += ds.rms;
      quadric_sum += dq.rms;
    }
    const double tolerance = std::string(name) == "sphere.obj" ? 1.03 : 1.0;
    EXPECT_LE(quadric_sum, tolerance * schroeder_sum) << name;
  }
}

TEST(BaseMesh, UnderOnePercentOfVerticesOnClosedOrganicMeshes) {
  PM_SKIP_IF_NO_SHARED();
  for (const char* name : {"armadillo.off", "homer.obj", "nefertiti.obj"}) {
    const Encoded e = encode_file(test::shared_mesh_path(name));
    EXPECT_LT(e.pm.base_vertex_count * 100, e.input.vertex_count())
        << name << ": base " << e.pm.base_vertex_count << " of " << e.input.vertex_count();
  }
}

TEST(BaseMesh, UnderTwoPercentOfVerticesOnTheBunny) {
  PM_SKIP_IF_NO_SHARED();
  const Encoded e = encode_file(test::shared_mesh_path("stanford-bunny.obj"));
  EXPECT_LT(e.pm.base_vertex_count * 50, e.input.vertex_count())
      << "base " << e.pm.base_vertex_count << " of " << e.input.vertex_count();
}

// The positions of the vertices Schroeder's classification calls corners, on the input;
// with sharp_deg > 0, only those with a feature edge sharper than that. Classified here on
// the repaired half-edge mesh, apart from the collapse loop's own classification
// (collapse_loop.h): a corner has one or three or more special edges, or is on a boundary with
// a feature edge (Schroeder, Zarge and Lorensen 1992, §3.1; Schroeder 1997, §3).
std::set<std::array<float, 3>> corner_positions(const Mesh& input, double feature_angle_deg,
                                                double sharp_deg = 0) {
  ManifoldMesh repaired;
  EXPECT_TRUE(build_manifold_mesh(input, repaired).is_ok());
  const HalfEdgeMesh& mesh = repaired.mesh;
  std::vector<Vec3> normal(mesh.n_faces());  // unit, or zero for a degenerate face
  for (auto f : mesh.faces()) {
    auto fv = mesh.cfv_iter(f);
    const Vec3 a = point_of(mesh, *fv), b = point_of(mesh, *++fv), c = point_of(mesh, *++fv);
    const Vec3 n = area_vector(a, b, c);
    normal[f.idx()] = n.norm() > 0 ? n / n.norm() : Vec3(0, 0, 0);
  }
  auto is_feature = [&](HalfEdgeMesh::EdgeHandle e, double cos_angle) {
    if (mesh.is_boundary(e)) return false;
    const auto f0 = mesh.face_handle(mesh.halfedge_handle(e, 0));
    const auto f1 = mesh.face_handle(mesh.halfedge_handle(e, 1));
    return (normal[f0.idx()] | normal[f1.idx()]) < cos_angle;
  };
  const double cos_angle = std::cos(feature_angle_deg * M_PI / 180.0);
  std::set<std::array<float, 3>> corners;
  for (auto v : mesh.vertices()) {
    if (mesh.is_isolated(v) || !mesh.is_manifold(v)) continue;
    int boundary_edges = 0, feature_edges = 0;
    for (auto h : mesh.voh_range(v)) {
      const bool boundary = mesh.is_boundary(mesh.edge_handle(h));
      boundary_edges += boundary;
      feature_edges += !boundary && is_feature(mesh.edge_handle(h), cos_angle);
    }
    if (kind_from_edges(boundary_edges, feature_edges) != VertexKind::kCorner) continue;
    bool sharp = sharp_deg <= 0;
    for (auto h : mesh.voh_range(v))
      sharp = sharp || is_feature(mesh.edge_handle(h), std::cos(sharp_deg * M_PI / 180.0));
    if (!sharp) continue;
    const auto& p = mesh.point(v);
    corners.insert({p[0], p[1], p[2]});
  }
  return corners;
}

// Every sharp corner of fandisk (a corner with an edge sharper than 60 degrees: the
// simplifier weighs their error tenfold) is still on the surface at 10% of the faces: kept
// as a vertex, or removed only where the surface that replaced it passes through it.
TEST(Features, FandiskKeepsEveryCornerAtTenPercent) {
  PM_SKIP_IF_NO_SHARED();
  // Schroeder's classification decides corners; the quadric metric has none by default.
  for (Metric metric : {Metric::kSchroeder, Metric::kQuadric}) {
    EncodeOptions options;
    options.metric = metric;
    const Encoded e = encode_file(test::shared_mesh_path("fandisk.obj"), options);
    const auto corners = corner_positions(e.input, 30.0, 60.0);
    ASSERT_GT(corners.size(), 10u) << "fandisk should have many sharp corners";
    const Mesh lod = extract_level(e.pm, level_for_faces(e.pm, e.input.face_count() / 10));
    std::set<std::array<float, 3>> present;
    for (std::size_t v = 0; v < lod.vertex_count(); ++v)
      present.insert({lod.positions[3 * v], lod.positions[3 * v + 1], lod.positions[3 * v + 2]});
    Mesh removed_corners;  // as point-like faces, whose samples are the points themselves
    for (const auto& c : corners) {
      if (present.count(c)) continue;
      const uint32_t v = uint32_t(removed_corners.vertex_count());
      removed_corners.positions.insert(removed_corners.positions.end(), c.begin(), c.end());
      removed_corners.triangles.insert(removed_corners.triangles.end(), {v, v, v});
    }
    std::printf("%s: %zu of %zu corners removed at %zu faces\n",
                metric == Metric::kQuadric ? "quadric" : "schroeder",
                removed_corners.vertex_count(), corners.size(), lod.face_count());
    if (removed_corners.vertex_count() == 0) continue;
    DistanceOptions one_sample;
    one_sample.samples_per_face = 1;
    SurfaceDistance d;
    ASSERT_TRUE(measure_surface_distance(removed_corners, lod, one_sample, d).is_ok());
    EXPECT_LE(d.forward_max, 1e-5 * bounding_box_diagonal(e.input.positions))
        << removed_corners.vertex_count() << " of " << corners.size() << " corners removed";
  }
}

TEST(Features, KeepCornersNeverRemovesACorner) {
  const std::string path = test::sample_mesh_path("block_features.obj");
  EncodeOptions options;
  options.metric = Metric::kSchroeder;
  options.keep_corners = true;
  const Encoded e = encode_file(path, options);
  const auto corners = corner_positions(e.input, effective_feature_angle(options));
  ASSERT_FALSE(corners.empty());
  const Mesh base = extract_level(e.pm, 0);
  std::set<std::array<float, 3>> present;
  for (std::size_t v = 0; v < base.vertex_count(); ++v)
    present.insert({base.positions[3 * v], base.positions[3 * v + 1], base.positions[3 * v + 2]});
  for (const auto& c : corners) EXPECT_TRUE(present.count(c));
}

TEST(Limits, MinFacesAndMinVerticesStopTheSimplification) {
  Mesh input;
  ASSERT_TRUE(read_mesh(test::sample_mesh_path("sphere.obj"), input).is_ok());
  // Either collapse loop; the fast one with one heap and in regions (whose rounds must
  // stop short of the limits, and leave the exact stop to the last heap).
  for (const int loop : {1, 2}) {
    SCOPED_TRACE(loop == 1 ? "one heap" : "regions");
    const auto loop_options = [loop] {
      EncodeOptions options;
      options.fast_partition_vertices = loop == 2 ? 1 : 0;
      return options;
    };
    for (const std::size_t min_faces : {input.face_count() / 4, input.face_count() / 40}) {
      EncodeOptions options = loop_options();
      options.min_faces = min_faces;
      ProgressiveMesh pm;
      ASSERT_TRUE(encode(input, options, pm).is_ok());
      EXPECT_GE(pm.base_face_count(), options.min_faces);
      EXPECT_LE(pm.base_face_count(), options.min_faces + 2);
    }
    for (const std::size_t min_vertices : {100, 700}) {
      EncodeOptions options = loop_options();
      options.min_vertices = min_vertices;
      ProgressiveMesh pm;
      ASSERT_TRUE(encode(input, options, pm).is_ok());
      EXPECT_EQ(pm.base_vertex_count, min_vertices);
    }
  }
}

}  // namespace
}  // namespace pm

namespace pm {
namespace {

// Odd real-world files (Debian's assimp-testmodels): every one that parses must come back
// exactly at full detail, whatever repairs it needed.
TEST(Robustness, AssimpModelsThatParseRoundTripExactly) {
  const std::string root = "/usr/share/assimp/models";
  if (!test::file_exists(root)) GTEST_SKIP() << root << " not found (package assimp-testmodels)";
  const test::CommandResult found =
      test::run_command({"find", root, "-type", "f", "(", "-iname", "*.obj", "-o", "-iname",
                         "*.ply", "-o", "-iname", "*.off", "-o", "-iname", "*.stl", ")"});
  ASSERT_EQ(found.exit_code, 0) << found.err;
  std::size_t parsed = 0;
  std::size_t start = 0;
  for (std::size_t end; (end = found.out.find('\n', start)) != std::string::npos; start = end + 1) {
    const std::string path = found.out.substr(start, end - start);
    Mesh input;
    if (!read_mesh(path, input)) continue;
    ++parsed;
    ProgressiveMesh pm;
    const Status s = encode(input, EncodeOptions{}, pm);  // attributes and all
    if (!s) {  // a mesh with vertices but no face is the only thing that may not encode
      EXPECT_EQ(s.code(), ErrorCode::kEmptyMesh) << path << ": " << s.message();
      continue;
    }
    const Mesh full = extract_level(pm, pm.split_count());
    EXPECT_TRUE(test::same_faces(input, full)) << path;
    EXPECT_TRUE(test::same_attributed_faces(input, full)) << path;
    EXPECT_EQ(full.vertex_count(), input.vertex_count()) << path;
  }
  EXPECT_GT(parsed, 20u);
}

// The collapse loop takes a manifold input as it is and sends every other through the repair
// first: small meshes of each kind come back exactly, every level with the input's topology.
TEST(FastLoop, SmallMeshesOfEveryKindRoundTripExactly) {
  auto mesh = [](std::vector<float> positions, std::vector<uint32_t> triangles) {
    Mesh m;
    m.positions = std::move(positions);
    m.triangles = std::move(triangles);
    return m;
  };
  // An octahedron: closed, every vertex of valence 4.
  const Mesh octahedron =
      mesh({1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1},
           {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5});
  // A fan of four triangles around vertex 0, open: a boundary all round.
  const Mesh fan = mesh({0, 0, 0, 1, 0, 0, 0, 1, 0.1f, -1, 0, 0, 0, -1, 0.1f},
                        {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1});
  struct Case {
    const char* name;
    Mesh input;
    bool repaired;  // the repair had something to do
  };
  std::vector<Case> cases = {{"octahedron", octahedron, false}, {"open fan", fan, false}};
  // Two fans meeting at one vertex (a bowtie).
  cases.push_back(
      {"bowtie", mesh({0, 0, 0, 1, 0, 0, 1, 1, 0, -1, 0, 0, -1, -1, 0}, {0, 1, 2, 0, 3, 4}), true});
  // The fan plus a vertex no face uses.
  Mesh loose = fan;
  loose.positions.insert(loose.positions.end(), {5, 5, 5});
  cases.push_back({"loose vertex", loose, true});
  // The octahedron plus a face with a repeated vertex.
  Mesh repeated = octahedron;
  repeated.triangles.insert(repeated.triangles.end(), {0, 0, 1});
  cases.push_back({"repeated vertex", repeated, true});
  // The fan with one face turned over: edge 0-2 twice the same way round.
  Mesh flipped = fan;
  std::swap(flipped.triangles[3], flipped.triangles[4]);
  cases.push_back({"inconsistent orientation", flipped, true});
  // A vertex whose one face repeats a vertex: the repair carries that face aside and leaves
  // the vertex without faces (found by fuzz_off_reader).
  Mesh carried = fan;
  carried.positions.insert(carried.positions.end(), {5, 5, 5});
  carried.triangles.insert(carried.triangles.end(), {1, 1, 5});
  cases.push_back({"vertex of a carried face only", carried, true});
  // Three faces on one edge.
  cases.push_back(
      {"complex edge",
       mesh({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1}, {0, 1, 2, 1, 0, 3, 0, 1, 4}), true});

  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    EncodeOptions options;
    ProgressiveMesh progressive;
    EncodeStats stats;
    ASSERT_TRUE(encode(c.input, options, progressive, &stats).is_ok());
    EXPECT_EQ(stats.repair.any(), c.repaired);
    EXPECT_TRUE(test::ok(validate(progressive)));
    const Mesh full = extract_level(progressive, progressive.split_count());
    EXPECT_TRUE(test::same_faces(c.input, full));
    EXPECT_EQ(full.vertex_count(), c.input.vertex_count());
    const test::TopologySummary in = test::summarize_topology(c.input);
    for (std::size_t level = 0; level <= progressive.split_count(); ++level)
      EXPECT_TRUE(
          test::keeps_topology(in, test::summarize_topology(extract_level(progressive, level))))
          << "level " << level;
  }
  // Both simplify as far as their topology allows: a closed surface to a tetrahedron's four
  // vertices, a disk to one triangle.
  ProgressiveMesh progressive;
  EncodeOptions options;
  ASSERT_TRUE(encode(octahedron, options, progressive).is_ok());
  EXPECT_EQ(progressive.base_vertex_count, 4u);
  ASSERT_TRUE(encode(fan, options, progressive).is_ok());
  EXPECT_EQ(progressive.base_vertex_count, 3u);
  EXPECT_EQ(progressive.base_face_count(), 1u);
}

// In regions, the levels stay as close to the input as the one-heap loop's, down to the
// coarse levels the last rounds make (when one order's cuts alone were used, vertices
// along them waited every round and hoarded the coarse levels' vertices: nefertiti's RMS
// distance at 3% of the faces was several times the one-heap loop's).
TEST(FastLoop, RegionsKeepTheLevelsAsCloseAsOneHeap) {
  const std::string path = test::shared_mesh_path("nefertiti.obj");
  if (!test::file_exists(path)) GTEST_SKIP() << path << " not found (../shared/meshes)";
  Mesh input;
  ASSERT_TRUE(read_mesh(path, input).is_ok());
  auto rms_at = [&](std::size_t partition_vertices, double ratio) {
    EncodeOptions options;
    options.fast_partition_vertices = partition_vertices;
    ProgressiveMesh pm;
    EXPECT_TRUE(encode(input, options, pm).is_ok());
    const auto faces = static_cast<std::size_t>(ratio * double(input.face_count()));
    SurfaceDistance d;
    EXPECT_TRUE(measure_surface_distance(input, extract_level(pm, level_for_faces(pm, faces)),
                                         DistanceOptions{}, d)
                    .is_ok());
    return d.rms;
  };
  for (const double ratio : {0.2, 0.05, 0.035}) {
    const double regions = rms_at(1, ratio), one_heap = rms_at(0, ratio);
    EXPECT_LE(regions, 1.25 * one_heap) << "at " << ratio << " of the faces";
  }
}

// A bumpy height field of side x side vertices: large enough for the collapse loop's regions
// to run rounds (on the few-thousand-vertex samples the cuts hold too many vertices, and
// one heap runs from the start).
Mesh bumpy_grid(uint32_t side) {
  Mesh m;
  for (uint32_t j = 0; j < side; ++j)
    for (uint32_t i = 0; i < side; ++i) {
      const float x = float(i) / float(side - 1), y = float(j) / float(side - 1);
      m.positions.insert(
          m.positions.end(),
          {x, y, 0.1f * std::sin(9 * x) * std::cos(7 * y) + 0.02f * std::sin(40 * x * y)});
    }
  for (uint32_t j = 0; j + 1 < side; ++j)
    for (uint32_t i = 0; i + 1 < side; ++i) {
      const uint32_t a = j * side + i, b = a + 1, c = a + side, d = c + 1;
      m.triangles.insert(m.triangles.end(), {a, b, d, a, d, c});
    }
  return m;
}

// In regions (EncodeOptions::fast_partition_vertices), the collapse loop makes its own
// sequence, the same every time and for any number of threads (their timing must not
// show), and every level of it a valid mesh.
TEST(FastLoop, RegionsMakeTheSameSequenceEveryTime) {
  const Mesh input = bumpy_grid(300);
  auto encoded = [&](std::size_t partition_vertices, unsigned threads, ProgressiveMesh& pm) {
    EncodeOptions options;
    options.fast_partition_vertices = partition_vertices;
    options.threads = threads;
    EncodeStats stats;
    EXPECT_TRUE(encode(input, options, pm, &stats).is_ok());
    std::string bytes;
    EXPECT_TRUE(write_pm(pm, WriteOptions{}, bytes).is_ok());
    return bytes;
  };
  ProgressiveMesh pm;
  const std::string regions = encoded(1, 0, pm);
  const test::TopologySummary in = test::summarize_topology(input);
  for (int i = 0; i <= 8; ++i) {
    const std::size_t level = pm.split_count() * i / 8;
    const Mesh lod = extract_level(pm, level);
    EXPECT_TRUE(test::keeps_topology(in, test::summarize_topology(lod))) << "level " << level;
    EXPECT_EQ(lod.face_count(), faces_at_level(pm, level));
  }
  EXPECT_TRUE(test::same_faces(input, extract_level(pm, pm.split_count())));
  for (int run = 0; run < 2; ++run) {
    ProgressiveMesh again;
    ASSERT_EQ(encoded(1, 0, again), regions) << "run " << run;
  }
  // Nor the number of threads: one, fewer than the regions, more. (With more than one, the
  // splits' layers, layer_splits, run in two stages on two threads too.)
  for (const unsigned threads : {1u, 3u, 12u}) {
    ProgressiveMesh again;
    EXPECT_EQ(encoded(1, threads, again), regions) << threads << " threads";
  }
  // Below the threshold, one heap: another order, so the rounds did run above.
  ProgressiveMesh one_heap, never;
  EXPECT_NE(encoded(input.vertex_count() + 1, 0, one_heap), regions);
  EXPECT_EQ(encoded(0, 0, never), encoded(input.vertex_count() + 1, 0, one_heap));
}

// After the rounds, with more than one thread, the moved points are tracked on a thread of
// their own (tracking_thread.h), a collapse behind the loop: the records must be those made
// in turn, with the measure and without it (whose points settle within the records so far).
TEST(FastLoop, TrackingThreadRecordsAsInTurn) {
  const Mesh input = bumpy_grid(160);  // 25,600 vertices: rounds first, then one heap
  for (const bool fast : {false, true}) {
    auto encoded = [&](unsigned threads) {
      EncodeOptions options;
      options.fast = fast;
      options.threads = threads;
      ProgressiveMesh pm;
      EXPECT_TRUE(encode(input, options, pm).is_ok());
      std::string bytes;
      EXPECT_TRUE(write_pm(pm, WriteOptions{}, bytes).is_ok());
      return bytes;
    };
    const std::string in_turn = encoded(1);
    EXPECT_EQ(encoded(2), in_turn) << (fast ? "fast" : "measured");
  }
}

// Without its measure, geometry only, the loop adds to the quadric's cost the largest squared
// distance from u to the planes of v's faces (collapse_loop.h, FanPlanes): the quadric is a
// mean, in which one face tilted far off its plane hides. On a bumpy height field the levels
// come closer to the input than on the quadric alone, at 10% and 2% of the faces; and the
// switch that turns it off does (CollapseLoop.ApexesKeepingTheirCandidate... relies on it).
TEST(FastLoop, ThePlaneTermBringsTheLevelsCloserToTheInput) {
  const Mesh input = bumpy_grid(120);
  EncodeOptions options;
  options.fast = true;
  auto distance_at = [&](bool plane_term, double ratio) {
    LoopSwitches switches;
    switches.plane_term = plane_term;
    ProgressiveMesh pm;
    EXPECT_TRUE(encode_with_switches(input, options, switches, pm).is_ok());
    const auto faces = static_cast<std::size_t>(ratio * double(input.face_count()));
    SurfaceDistance d;
    EXPECT_TRUE(measure_surface_distance(input, extract_level(pm, level_for_faces(pm, faces)),
                                         DistanceOptions{}, d)
                    .is_ok());
    return d;
  };
  for (const double ratio : {0.1, 0.02}) {
    const SurfaceDistance with = distance_at(true, ratio), without = distance_at(false, ratio);
    // Measured: Hausdorff 0.68 and 0.61 times, RMS 0.88 and 0.89 times the quadric's alone.
    EXPECT_LT(with.hausdorff, 0.8 * without.hausdorff) << "at " << ratio << " of the faces";
    EXPECT_LT(with.rms, 0.95 * without.rms) << "at " << ratio << " of the faces";
  }
}

// A mesh and a metric whose sequences a test compares: the textured sample with either
// metric, then each of the shared meshes `shared` that is there with each of `metrics`.
struct SequenceCase {
  std::string path;
  Metric metric;
};
std::vector<SequenceCase> sequence_cases(std::initializer_list<const char*> shared,
                                         std::initializer_list<Metric> metrics) {
  std::vector<SequenceCase> cases = {{test::sample_mesh_path("textured.obj"), Metric::kQuadric},
                                     {test::sample_mesh_path("textured.obj"), Metric::kSchroeder}};
  for (const char* name : shared) {
    const std::string path = test::shared_mesh_path(name);
    if (!test::file_exists(path)) {
      std::fprintf(stderr, "[  SKIPPED ] %s not found (../shared/meshes)\n", path.c_str());
      continue;
    }
    for (const Metric metric : metrics) cases.push_back({path, metric});
  }
  return cases;
}

// The whole collapse sequence as encode() runs it (on the input, or on its repair) with
// the loop's test switches, written out: every collapse with its record and moved faces,
// the attribute record and the base mesh; and the number of collapses.
// `renamings`, when set: how often the loop renamed its faces (compact_faces()).
std::pair<std::size_t, std::vector<double>> whole_sequence(const Mesh& input,
                                                           const EncodeOptions& options,
                                                           const LoopSwitches& switches,
                                                           std::size_t* renamings = nullptr) {
  Simplification run;
  if (!simplify_direct(input, options, run, switches)) {
    ManifoldMesh repaired;
    EXPECT_TRUE(build_manifold_mesh(input, repaired).is_ok());
    EXPECT_TRUE(simplify(input, repaired, options, run, switches).is_ok());
  }
  std::vector<double> words;
  auto add = [&](const auto& values) {
    words.push_back(-1.0);  // a separator, so that no two layouts run together
    for (const auto x : values) words.push_back(static_cast<double>(x));
  };
  for (const Collapse& c : run.collapses)
    add(std::vector<double>{double(c.v), double(c.u), double(c.vl), double(c.vr), double(c.fl),
                            double(c.fr), double(c.moved_begin), double(c.moved_count),
                            double(c.new_faces_begin), double(c.bound)});
  add(run.moved_faces.entries());
  add(run.attribute_record.moved_uvs.entries());
  add(run.attribute_record.moved_normals.entries());
  add(run.attribute_record.new_face_uvs.entries());
  add(run.attribute_record.new_face_normals.entries());
  add(run.base.vertices);
  add(run.base.faces);
  add(run.base.corners);
  if (renamings) *renamings = run.face_renamings;
  return {run.collapses.size(), words};
}

// Between rounds the loop renames its faces without the dead ones and shrinks its per-face
// arrays (face_renumbering.h). Every live face keeps its place among the others, so the
// sequence, its records (in the given ids) and the .pm are the ones the loop makes without
// renaming: with and without the measure, with texture coordinates, normals and materials
// (the textured sample: the dead faces' materials are kept aside for their splits) and
// without, either metric.
TEST(CollapseLoop, RenamingTheFacesBetweenRoundsChangesNothing) {
  std::size_t measured_renamings = 0;
  for (const SequenceCase& c :
       sequence_cases({"fandisk.obj", "spot.obj", "stanford-bunny.obj"}, {Metric::kQuadric})) {
    Mesh input;
    ASSERT_TRUE(read_mesh(c.path, input).is_ok()) << c.path;
    for (const bool fast : {false, true}) {
      SCOPED_TRACE(c.path + (fast ? ", fast" : ", measured") +
                   (c.metric == Metric::kSchroeder ? ", schroeder" : ", quadric"));
      EncodeOptions options;
      options.metric = c.metric;
      options.fast = fast;
      options.fast_partition_vertices = 1;  // rounds, whatever the size
      LoopSwitches renaming, keeping;
      keeping.compact_faces = false;
      std::size_t renamed = 0, kept_names = 0;
      const auto with = whole_sequence(input, options, renaming, &renamed);
      const auto without = whole_sequence(input, options, keeping, &kept_names);
      // Without the measure the rounds go on to a sixteenth of the vertices and rename the
      // faces every time; with it a small mesh's rounds may end before a quarter of its
      // faces are dead (below).
      if (fast) {
        EXPECT_GT(renamed, 0u);
      }
      measured_renamings += fast ? 0 : renamed;
      EXPECT_EQ(kept_names, 0u);
      EXPECT_GT(with.first, 0u);
      EXPECT_TRUE(with == without) << "the sequences differ: " << with.first << " and "
                                   << without.first << " collapses";
      ProgressiveMesh pm_with, pm_without;
      ASSERT_TRUE(encode_with_switches(input, options, renaming, pm_with).is_ok());
      ASSERT_TRUE(encode_with_switches(input, options, keeping, pm_without).is_ok());
      std::string bytes_with, bytes_without;
      ASSERT_TRUE(write_pm(pm_with, WriteOptions{}, bytes_with).is_ok());
      ASSERT_TRUE(write_pm(pm_without, WriteOptions{}, bytes_without).is_ok());
      EXPECT_TRUE(bytes_with == bytes_without) << "the .pm streams differ";
      EXPECT_EQ(pm_with.face_materials, pm_without.face_materials);
    }
  }
  EXPECT_GT(measured_renamings, 0u) << "no measured case renamed its faces";
}

// The collapse loop with its measure keeps the fan's part of a candidate's measure while
// only points move onto its faces (collapse_measure.cpp). That only saves work: with the
// same steps and keys as a measure from nothing, the sequence is the same, with attributes
// and without, either metric, in one heap and in regions. (Not guaranteed everywhere: the
// input distance's search starts from the kept points, which move, and a measure's rounding
// depends on the distance it starts from; on nefertiti after a Loop step, 1 of 20,761 reused
// parts differs from a fresh measure. None does on these meshes.)
TEST(MeasuredLoop, KeepingTheFansPartOfAMeasureChangesNoCollapse) {
  for (const SequenceCase& c : sequence_cases({"spot.obj", "homer.obj", "cow.obj"},
                                              {Metric::kQuadric, Metric::kSchroeder})) {
    Mesh input;
    ASSERT_TRUE(read_mesh(c.path, input).is_ok()) << c.path;
    for (const bool regions : {false, true}) {
      SCOPED_TRACE(c.path + (c.metric == Metric::kSchroeder ? " schroeder" : " quadric") +
                   (regions ? ", regions" : ", one heap"));
      EncodeOptions options;
      options.metric = c.metric;
      options.fast_partition_vertices = regions ? 1 : 0;
      LoopSwitches measure_again;
      measure_again.reuse_fan_part = false;
      const auto kept = whole_sequence(input, options, LoopSwitches{});
      const auto measured = whole_sequence(input, options, measure_again);
      EXPECT_GT(kept.first, 0u);
      EXPECT_TRUE(kept == measured) << "the sequences differ: " << kept.first << " and "
                                    << measured.first << " collapses";
    }
  }
}

// After a collapse v -> u, the apexes vl and vr keep their queued candidate when it was their
// cheapest option and not towards v (geometry only): evaluated again, they would queue the
// same one (their other options cost what they did, and ties go by the neighbour's id, not
// by the ring walk's start, which the collapse moves). So the sequence is the one that
// evaluates them again, with and without the measure, in one heap and in regions, on a mesh
// of flat parts full of ties (fandisk) and on curved ones. Without the measure, on the
// quadric alone: the plane term of an apex's options moves with its faces at v, which the
// shortcut leaves as they were (collapse_apply.cpp; FastLoop.ThePlaneTerm... above).
TEST(CollapseLoop, ApexesKeepingTheirCandidateChangesNoCollapse) {
  std::vector<std::string> paths = {test::sample_mesh_path("textured.obj")};
  for (const char* name : {"fandisk.obj", "homer.obj", "rocker-arm.obj", "spot.obj"}) {
    const std::string path = test::shared_mesh_path(name);
    if (!test::file_exists(path)) {
      std::fprintf(stderr, "[  SKIPPED ] %s not found (../shared/meshes)\n", path.c_str());
      continue;
    }
    paths.push_back(path);
  }
  for (const std::string& path : paths) {
    Mesh input;
    ASSERT_TRUE(read_mesh(path, input).is_ok()) << path;
    EncodeOptions options;
    options.drop_attributes = true;  // the shortcut is for geometry only
    for (const bool fast : {false, true})
      for (const bool regions : {false, true}) {
        SCOPED_TRACE(path + (fast ? ", fast" : ", measured") + (regions ? ", regions" : ", one heap"));
        options.fast = fast;
        options.fast_partition_vertices = regions ? 1 : 0;
        LoopSwitches keep, evaluate_again;
        keep.plane_term = evaluate_again.plane_term = false;
        evaluate_again.keep_apex_candidates = false;
        const auto kept = whole_sequence(input, options, keep);
        const auto evaluated = whole_sequence(input, options, evaluate_again);
        EXPECT_GT(kept.first, 0u);
        EXPECT_TRUE(kept == evaluated) << "the sequences differ: " << kept.first << " and "
                                       << evaluated.first << " collapses";
      }
  }
}

// Without its measure, with attributes, the loop queues a vertex whose cheapest geometric
// cost already ranks behind the heap's top at that cost, a lower bound, and prices its
// attribute error only if it comes to the top (LoopSwitches::price_at_top). The texture must
// still weigh in every collapse: on a surface whose two halves have the same bumps, the
// half whose texture is stretched nonlinearly keeps more of the vertices at every coarser
// level than the half mapped linearly, priced at the top or at every evaluation, in one
// heap and in regions; and the two ways keep about as many. (Measured, in regions, at 30%,
// 10% and 3% of the faces: 4,462 against 3,256, 1,827 against 797 and 567 against 246
// vertices. A vertex collapsed once it came to the top unpriced, its attribute error never
// asked: 3,945 against 3,735, 1,380 against 1,216, 471 against 327.)
TEST(FastLoop, PricedAtTheTopTheTextureStillWeighs) {
  constexpr uint32_t kSide = 160;  // 25,600 vertices: rounds run in regions
  Mesh m;
  for (uint32_t j = 0; j < kSide; ++j)
    for (uint32_t i = 0; i < kSide; ++i) {
      const float x = float(i) / float(kSide - 1), y = float(j) / float(kSide - 1);
      m.positions.insert(m.positions.end(),
                         {x, y, 0.02f * std::cos(20 * (x - 0.5f)) * std::cos(14 * y)});
      m.uvs.insert(m.uvs.end(), {x, x < 0.5f ? y + 0.15f * std::sin(40 * x) : y});
    }
  for (uint32_t j = 0; j + 1 < kSide; ++j)
    for (uint32_t i = 0; i + 1 < kSide; ++i) {
      const uint32_t a = j * kSide + i, b = a + 1, c = a + kSide, d = c + 1;
      m.triangles.insert(m.triangles.end(), {a, b, d, a, d, c});
    }
  m.uv_indices = m.triangles;
  std::string streams[2][2];  // [in regions][priced at the top]
  for (const bool regions : {false, true}) {
    EncodeOptions options;
    options.fast = true;
    options.fast_partition_vertices = regions ? 1 : 0;
    std::size_t left_at[2][3] = {};
    for (const bool at_top : {true, false}) {
      SCOPED_TRACE(std::string(regions ? "regions" : "one heap") +
                   (at_top ? ", priced at the top" : ", priced at every evaluation"));
      LoopSwitches switches;
      switches.price_at_top = at_top;
      ProgressiveMesh pm;
      ASSERT_TRUE(encode_with_switches(m, options, switches, pm).is_ok());
      ASSERT_TRUE(write_pm(pm, WriteOptions{}, streams[regions][at_top]).is_ok());
      int k = 0;
      for (const double ratio : {0.3, 0.1, 0.03}) {
        const Mesh lod = extract_level(
            pm, level_for_faces(pm, static_cast<std::size_t>(ratio * double(m.face_count()))));
        std::size_t left = 0, right = 0;
        for (std::size_t x = 0; x < lod.vertex_count(); ++x)
          ++(lod.positions[3 * x] < 0.5f ? left : right);
        EXPECT_GT(left, right + right / 4) << "at " << ratio << " of the faces";
        left_at[at_top][k++] = left;
      }
    }
    for (int k = 0; k < 3; ++k) {
      EXPECT_LT(left_at[1][k], left_at[0][k] + left_at[0][k] / 5) << "level " << k;
      EXPECT_GT(left_at[1][k], left_at[0][k] - left_at[0][k] / 5) << "level " << k;
    }
  }
  EXPECT_FALSE(streams[0][1] == streams[1][1]) << "the rounds did not run";
  for (const bool regions : {false, true})
    EXPECT_FALSE(streams[regions][0] == streams[regions][1]) << "priced at the top: no change";
}

// A 3 x 3 grid at z = -h, its centre raised to z = +h, spacing s; faces a-b-c and a-c-d of
// each cell, from its lower left corner a:
//
//   6---7---8
//   | / | / |
//   3---4---5      4 at z = +h, the others at z = -h
//   | / | / |
//   0---1---2
Mesh spike_grid(float s, float h) {
  Mesh mesh;
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 3; ++x)
      mesh.positions.insert(mesh.positions.end(), {x * s, y * s, x == 1 && y == 1 ? h : -h});
  }
  for (uint32_t y = 0; y < 2; ++y) {
    for (uint32_t x = 0; x < 2; ++x) {
      const uint32_t a = 3 * y + x;
      mesh.triangles.insert(mesh.triangles.end(), {a, a + 1, a + 4, a, a + 4, a + 3});
    }
  }
  return mesh;
}

// Found by fuzz_ply_reader: with finite coordinates near the float32 limit, the error a
// collapse records (a distance across the mesh) overflowed float32, and encode() failed with
// kInternal. Errors are at most the bounding-box diagonal, so a mesh within
// kMaxEncodeDiagonal records finite ones, and a wider one is refused.
TEST(Robustness, MeshesTooWideForFloatErrorsAreRefused) {
  for (Metric metric : {Metric::kSchroeder, Metric::kQuadric}) {
    SCOPED_TRACE(metric == Metric::kQuadric ? "quadric" : "schroeder");
    EncodeOptions options;
    options.metric = metric;
    ProgressiveMesh pm;
    // 6.6e37 across; the spike is 6e37 tall.
    const Status within = encode(spike_grid(1e37f, 3e37f), options, pm);
    ASSERT_TRUE(within.is_ok()) << within.message();
    ASSERT_FALSE(pm.splits.empty());
    EXPECT_GT(pm.splits[0].error, 1e37f);
    EXPECT_TRUE(std::isfinite(pm.splits[0].error));
    // 6.6e38 across: the spike, 6e38 tall, is beyond float32's 3.4e38.
    const Status beyond = encode(spike_grid(1e38f, 3e38f), options, pm);
    EXPECT_EQ(beyond.code(), ErrorCode::kResourceLimit) << beyond.message();
    EXPECT_EQ(beyond.message(), "the mesh is 6.63e+38 units across, more than 1e+38");
  }
}

// A textured mesh 10^30 units across: its face areas, 10^58, and the attribute errors' scale
// squared, 10^60, are beyond float's range (the wedges' float quadrics saturated there, before
// the attribute error went memoryless, in double) and stay finite in double.
TEST(Robustness, TexturedMeshesNearTheWidthLimitEncode) {
  Mesh wide = test::seamed_grid(8);
  for (float& x : wide.positions) x *= 1e30f;
  for (Metric metric : {Metric::kSchroeder, Metric::kQuadric}) {
    SCOPED_TRACE(metric == Metric::kQuadric ? "quadric" : "schroeder");
    EncodeOptions options;
    options.metric = metric;
    ProgressiveMesh pm;
    const Status status = encode(wide, options, pm);
    ASSERT_TRUE(status.is_ok()) << status.message();
    ASSERT_FALSE(pm.splits.empty());
    for (const VertexSplit& split : pm.splits) ASSERT_TRUE(std::isfinite(split.error));
    EXPECT_EQ(extract_level(pm, pm.split_count()).face_count(), wide.face_count());
    EXPECT_FALSE(pm.uvs.empty());
  }
}

// The readers refuse them; a caller's mesh may still hold them.
TEST(Robustness, NonFiniteCoordinatesAreAnInvalidArgument) {
  for (float bad : {NAN, INFINITY, -INFINITY}) {
    Mesh mesh = spike_grid(1.0f, 1.0f);
    mesh.positions[3 * 4 + 1] = bad;
    ProgressiveMesh pm;
    const Status status = encode(mesh, EncodeOptions{}, pm);
    EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument);
    EXPECT_EQ(status.message(), "vertex 5 has a non-finite coordinate");
  }
}

// encode(Mesh&&) lets the input's arrays go once the loop has its own copies (pmenc's way):
// the same progressive mesh as encode(const Mesh&) makes, on the direct path and through
// the repair (whose loose vertex and carried face assemble() still reads from the input),
// with every option that reads the input after the loop; and the input is left empty.
TEST(EncodeTakingTheMesh, MakesTheSameStreamAndLeavesTheInputEmpty) {
  Mesh textured;
  ASSERT_TRUE(read_mesh(test::sample_mesh_path("textured.obj"), textured).is_ok());
  ASSERT_TRUE(textured.has_uvs() && textured.has_normals() && textured.has_materials());
  // A fan with texture coordinates, a material per face and a colour per vertex, plus a
  // vertex whose one face repeats a vertex: the repair carries that face aside and leaves
  // the vertex without faces.
  Mesh carried;
  carried.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0.1f, -1, 0, 0, 0, -1, 0.1f, 5, 5, 5};
  carried.triangles = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1, 1, 1, 5};
  carried.uvs = {0, 0, 1, 0, 0, 1, 1, 1};
  carried.uv_indices = {0, 1, 2, 0, 2, 3, 0, 3, 1, 0, 1, 2, 3, 3, 0};
  carried.face_materials = {0, 0, 1, 1, 1};
  carried.material_names = {"a", "b"};
  carried.color_components = 3;
  for (int v = 0; v < 6; ++v) carried.colors.insert(carried.colors.end(), {0.1f * v, 0.5f, 1});
  struct Case {
    const char* name;
    const Mesh* input;
    bool keep_order, drop_attributes, fast;
  };
  const Case cases[] = {{"textured", &textured, false, false, false},
                        {"textured, --keep-order", &textured, true, false, false},
                        {"textured, --drop-attributes", &textured, false, true, false},
                        {"textured, --fast", &textured, false, false, true},
                        {"carried face and loose vertex", &carried, false, false, false},
                        {"carried face and loose vertex, --keep-order", &carried, true, false, false}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    EncodeOptions options;
    options.keep_order = c.keep_order;
    options.drop_attributes = c.drop_attributes;
    options.fast = c.fast;
    ProgressiveMesh kept, taken;
    EncodeStats kept_stats, taken_stats;
    ASSERT_TRUE(encode(*c.input, options, kept, &kept_stats).is_ok());
    Mesh given = *c.input;
    ASSERT_TRUE(encode(std::move(given), options, taken, &taken_stats).is_ok());
    EXPECT_TRUE(given.positions.empty() && given.triangles.empty() && given.uvs.empty() &&
                given.uv_indices.empty() && given.colors.empty() && given.material_names.empty());
    std::string kept_bytes, taken_bytes;
    ASSERT_TRUE(write_pm(kept, WriteOptions{}, kept_bytes).is_ok());
    ASSERT_TRUE(write_pm(taken, WriteOptions{}, taken_bytes).is_ok());
    EXPECT_EQ(kept_bytes, taken_bytes);
    EXPECT_EQ(taken_stats.input_faces, c.input->face_count());
    EXPECT_EQ(taken_stats.repair.any(), kept_stats.repair.any());
    // Full detail is still the input, attributes and all (unless dropped).
    const Mesh full = extract_level(taken, taken.split_count());
    EXPECT_TRUE(test::same_faces(*c.input, full));
    if (!c.drop_attributes) {
      EXPECT_TRUE(test::same_attributed_faces(*c.input, full));
    }
  }
  // The input is left empty when encode() refuses it too.
  Mesh out_of_range;
  out_of_range.positions = {0, 0, 0};
  out_of_range.triangles = {0, 1, 2};
  ProgressiveMesh refused;
  EXPECT_EQ(encode(std::move(out_of_range), EncodeOptions{}, refused).code(),
            ErrorCode::kInvalidArgument);
  EXPECT_TRUE(out_of_range.positions.empty() && out_of_range.triangles.empty());
}

}  // namespace
}  // namespace pm
