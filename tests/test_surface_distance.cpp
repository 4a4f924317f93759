// measure_surface_distance against answers known in closed form, and pmdec --compare.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <utility>

#include "pm/mesh_io.h"
#include "pm/surface_distance.h"
#include "test_util.h"

namespace pm {
namespace {

SurfaceDistance measure(const Mesh& reference, const Mesh& other, DistanceOptions options = {}) {
  SurfaceDistance distance;
  const Status s = measure_surface_distance(reference, other, options, distance);
  EXPECT_TRUE(s.is_ok()) << s.message();
  return distance;
}

Mesh scaled(Mesh mesh, float factor) {
  for (float& coordinate : mesh.positions) coordinate *= factor;
  return mesh;
}

// An icosahedron subdivided `levels` times (each triangle into four by its edge midpoints),
// every vertex projected onto the unit sphere: 20 * 4^levels flat faces.
Mesh unit_icosphere(int levels) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<std::array<double, 3>> points = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                               {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                               {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<uint32_t> triangles = {0, 11, 5, 0, 5,  1,  0,  1,  7,  0,  7, 10, 0, 10, 11,
                                     1, 5,  9, 5, 11, 4,  11, 10, 2,  10, 7, 6,  7, 1,  8,
                                     3, 9,  4, 3, 4,  2,  3,  2,  6,  3,  6, 8,  3, 8,  9,
                                     4, 9,  5, 2, 4,  11, 6,  2,  10, 8,  6, 7,  9, 8,  1};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      auto [it, inserted] = midpoints.emplace(key, uint32_t(points.size()));
      if (inserted) {
        points.push_back({(points[a][0] + points[b][0]) / 2, (points[a][1] + points[b][1]) / 2,
                          (points[a][2] + points[b][2]) / 2});
      }
      return it->second;
    };
    std::vector<uint32_t> finer;
    for (std::size_t f = 0; f < triangles.size(); f += 3) {
      const uint32_t a = triangles[f], b = triangles[f + 1], c = triangles[f + 2];
      const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      finer.insert(finer.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    triangles = std::move(finer);
  }
  Mesh mesh;
  for (const auto& p : points) {
    const double length = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int axis = 0; axis < 3; ++axis) mesh.positions.push_back(float(p[axis] / length));
  }
  mesh.triangles = std::move(triangles);
  return mesh;
}

// The unit square [0, 1]^2 at height z, as an n x n grid of quads, two triangles each.
Mesh square_grid(int n, float z) {
  Mesh mesh;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      mesh.positions.insert(mesh.positions.end(), {i / float(n), j / float(n), z});
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const uint32_t v = uint32_t(j * (n + 1) + i), up = v + uint32_t(n + 1);
      mesh.triangles.insert(mesh.triangles.end(), {v, v + 1, up + 1, v, up + 1, up});
    }
  }
  return mesh;
}

Mesh one_triangle(float apex_height) {
  Mesh mesh;
  mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, apex_height};
  mesh.triangles = {0, 1, 2};
  return mesh;
}

TEST(SurfaceDistance, AMeshAgainstItselfIsExactlyZero) {
  Mesh sphere;
  ASSERT_TRUE(read_mesh(test::sample_mesh_path("sphere.obj"), sphere).is_ok());
  for (const Mesh& mesh : {unit_icosphere(3), square_grid(7, 0.5f), sphere}) {
    const SurfaceDistance d = measure(mesh, mesh);
    EXPECT_EQ(d.hausdorff, 0.0);
    EXPECT_EQ(d.rms, 0.0);
    EXPECT_EQ(d.forward_max, 0.0);
    EXPECT_EQ(d.backward_max, 0.0);
    EXPECT_GT(d.samples, 2 * 10 * mesh.face_count());
  }
}

TEST(SurfaceDistance, IcosphereAgainstItsCopyScaledBy1Point01) {
  // Both are convex polyhedra, the copy outside. A point of the copy's face j is at distance
  // 0.01 h_j from the original's face plane j (h_j: that plane's distance from the centre)
  // and at most 0.01 |p| <= 0.01 from the original point it was scaled from; at a vertex,
  // 1.01 v, the distance is exactly 0.01 (v is the nearest point of the inscribed hull).
  // A point p inside face j of the original is min_k(1.01 h_k - p.n_k) >= 0.01 min_k h_k
  // from the copy and 0.01 h_j <= 0.01 from it. With 1280 faces, h > 0.99 for every face,
  // so every sample's distance lies in [0.0099, 0.01], up to the float rounding of the
  // scaled vertices (1e-7 relative). Vertices are always samples: the maximum is attained.
  const Mesh sphere = unit_icosphere(3);
  ASSERT_EQ(sphere.face_count(), 1280u);
  const Mesh larger = scaled(sphere, 1.01f);
  const SurfaceDistance d = measure(sphere, larger);
  EXPECT_NEAR(d.hausdorff, 0.01, 1e-6);
  EXPECT_NEAR(d.backward_max, 0.01, 1e-6);
  EXPECT_GE(d.forward_max, 0.0099);
  EXPECT_LE(d.forward_max, 0.01 + 1e-6);
  for (double rms : {d.rms, d.forward_rms, d.backward_rms}) {
    EXPECT_GE(rms, 0.0099);
    EXPECT_LE(rms, 0.01 + 1e-6);
  }
}

TEST(SurfaceDistance, PlaneAgainstItsOffsetCopy) {
  // Every point of either square is right above or below a point of the other.
  const double offset = 0.25;
  const SurfaceDistance d = measure(square_grid(8, 0), square_grid(8, float(offset)));
  EXPECT_NEAR(d.hausdorff, offset, 1e-6);
  EXPECT_NEAR(d.rms, offset, 1e-6);
  EXPECT_NEAR(d.forward_max, offset, 1e-6);
  EXPECT_NEAR(d.backward_max, offset, 1e-6);
  EXPECT_NEAR(d.forward_rms, offset, 1e-6);
  EXPECT_NEAR(d.backward_rms, offset, 1e-6);
  EXPECT_NEAR(d.diagonal, std::sqrt(2.0), 1e-6);
  // Different triangulations of the same square are at distance 0 from each other.
  EXPECT_NEAR(measure(square_grid(8, 0), square_grid(3, 0)).hausdorff, 0, 1e-12);
}

TEST(SurfaceDistance, TriangleAgainstItselfWithTheApexRaised) {
  // A = (0,0,0) (1,0,0) (0,1,0); B has its apex raised to (0,1,h). B's point (x, y, y h) is
  // y h above A's point (x, y, 0), the nearest: backward max h, at the apex. A's point
  // (x, y, 0) is y h / sqrt(1 + h^2) from B's plane, whose foot lies inside B: forward max
  // h / sqrt(1 + h^2), at A's apex. Over a uniform triangle the mean of y^2 is 1/6, so the
  // RMS are those maxima over sqrt(6), up to sampling noise (10^4 stratified samples: 1%).
  const double h = 0.5;
  DistanceOptions dense;
  dense.samples_per_face = 10000;
  const SurfaceDistance d = measure(one_triangle(0), one_triangle(float(h)), dense);
  const double slant = std::sqrt(1 + h * h);
  EXPECT_NEAR(d.backward_max, h, 1e-9);
  EXPECT_NEAR(d.forward_max, h / slant, 1e-9);
  EXPECT_NEAR(d.hausdorff, h, 1e-9);
  EXPECT_NEAR(d.backward_rms, h / std::sqrt(6.0), 0.01 * h);
  EXPECT_NEAR(d.forward_rms, h / slant / std::sqrt(6.0), 0.01 * h);
  EXPECT_NEAR(d.rms,
              std::sqrt((d.forward_rms * d.forward_rms + d.backward_rms * d.backward_rms) / 2),
              1e-9);  // both sides have the same number of samples
}

TEST(SurfaceDistance, SampleCounts) {
  // 3 vertices plus m^2 points for m = ceil(sqrt(samples_per_face)): 4^2 for 10, each way.
  EXPECT_EQ(measure(one_triangle(0), one_triangle(1)).samples, 2u * (3 + 16));
  DistanceOptions options;
  options.samples_per_face = 1;
  EXPECT_EQ(measure(one_triangle(0), one_triangle(1), options).samples, 2u * (3 + 1));
  // Faces larger than the mean get proportionally more: here a 1x1 triangle and a 0.1 x 0.1
  // one; mean area 0.2525, so the large one wants 10 * 0.5 / 0.2525 = 19.8 -> 5^2 samples.
  Mesh two = one_triangle(0);
  two.positions.insert(two.positions.end(), {5, 5, 0, 5.1f, 5, 0, 5, 5.1f, 0});
  two.triangles.insert(two.triangles.end(), {3, 4, 5});
  EXPECT_EQ(measure(two, one_triangle(0)).samples, (6 + 25 + 16) + (3 + 16));
}

TEST(SurfaceDistance, DeterministicWhateverTheThreadCount) {
  const Mesh sphere = unit_icosphere(4);  // 5120 faces: several chunks of work
  const Mesh coarser = scaled(unit_icosphere(2), 1.02f);
  DistanceOptions one_thread, two_threads;
  one_thread.threads = 1;
  two_threads.threads = 2;
  const SurfaceDistance a = measure(sphere, coarser, one_thread);
  const SurfaceDistance b = measure(sphere, coarser, two_threads);
  EXPECT_EQ(a.hausdorff, b.hausdorff);
  EXPECT_EQ(a.rms, b.rms);
  EXPECT_EQ(a.forward_rms, b.forward_rms);
  EXPECT_EQ(a.backward_rms, b.backward_rms);
  EXPECT_EQ(a.samples, b.samples);
  DistanceOptions other_seed;
  other_seed.seed = 7;
  EXPECT_NE(measure(sphere, coarser, other_seed).forward_rms, a.forward_rms);
}

TEST(SurfaceDistance, Errors) {
  const Mesh good = one_triangle(0);
  SurfaceDistance out;
  auto code = [&](const Mesh& reference, const Mesh& other, DistanceOptions options = {}) {
    return measure_surface_distance(reference, other, options, out).code();
  };
  Mesh no_faces = good;
  no_faces.triangles.clear();
  EXPECT_EQ(code(no_faces, good), ErrorCode::kInvalidArgument);
  EXPECT_EQ(code(good, no_faces), ErrorCode::kInvalidArgument);
  EXPECT_EQ(code(Mesh(), good), ErrorCode::kInvalidArgument);
  Mesh out_of_range = good;
  out_of_range.triangles[2] = 3;
  EXPECT_EQ(code(out_of_range, good), ErrorCode::kInvalidArgument);
  EXPECT_EQ(code(good, out_of_range), ErrorCode::kInvalidArgument);
  Status s = measure_surface_distance(good, out_of_range, {}, out);
  EXPECT_EQ(s.message(), "other mesh: face 0 uses vertex 3 of 3");
  for (float bad :
       {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    Mesh non_finite = good;
    non_finite.positions[4] = bad;
    EXPECT_EQ(code(non_finite, good), ErrorCode::kInvalidArgument);
    EXPECT_EQ(code(good, non_finite), ErrorCode::kInvalidArgument);
  }
  for (double samples : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                         std::numeric_limits<double>::infinity()}) {
    DistanceOptions options;
    options.samples_per_face = samples;
    EXPECT_EQ(code(good, good, options), ErrorCode::kInvalidArgument) << samples;
  }
  // Degenerate faces and unreferenced vertices are fine.
  Mesh odd = good;
  odd.positions.insert(odd.positions.end(), {7, 7, 7, 2, 0, 0});
  odd.triangles.insert(odd.triangles.end(), {1, 1, 4});
  EXPECT_EQ(code(odd, good), ErrorCode::kOk);
  EXPECT_NEAR(out.forward_max, 1.0, 1e-9);  // (2, 0, 0) to (1, 0, 0); (7, 7, 7) is no sample
}

// pmdec --compare, end to end.
test::CommandResult run(std::vector<std::string> args, const char* tool) {
  args.insert(args.begin(), tool);
  return test::run_command(args);
}

TEST(PmdecCompare, FullDetailIsAtDistanceZeroFromTheOriginal) {
  test::TempDir dir;
  const std::string original = test::sample_mesh_path("sphere.obj");
  ASSERT_EQ(run({original, "-o", dir.file("s.pm"), "-q"}, PMENC_PATH).exit_code, 0);

  test::CommandResult r =
      run({dir.file("s.pm"), "--ratio", "1", "--compare", original, "-q"}, PMDEC_PATH);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("hausdorff 0 (0% of diagonal) rms 0 (0%) faces 5120 samples ", 0), 0u)
      << r.out;
  EXPECT_EQ(r.err, "");

  r = run({dir.file("s.pm"), "--ratio", "1", "--compare", original, "--json", "-q"}, PMDEC_PATH);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_FALSE(r.out.empty());
  EXPECT_EQ(r.out.front(), '{');
  EXPECT_EQ(r.out.substr(r.out.size() - 2), "}\n");
  for (const char* key : {"\"faces\":5120,", "\"vertices\":2562,", "\"level\":", "\"hausdorff\":0,",
                          "\"rms\":0,", "\"hausdorff_percent\":0,", "\"rms_percent\":0,",
                          "\"diagonal\":", "\"samples\":", "\"seconds\":"})
    EXPECT_NE(r.out.find(key), std::string::npos) << key << " in " << r.out;
}

TEST(PmdecCompare, CoarseLevelsAreFartherAndAnOutputIsStillWritten) {
  test::TempDir dir;
  const std::string original = test::sample_mesh_path("sphere.obj");
  ASSERT_EQ(run({original, "-o", dir.file("s.pm"), "-q"}, PMENC_PATH).exit_code, 0);
  const test::CommandResult r = run(
      {dir.file("s.pm"), "--ratio", "0.1", "--compare", original, "-o", dir.file("c.obj"), "-q"},
      PMDEC_PATH);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  double hausdorff = 0, rms = 0;
  ASSERT_EQ(std::sscanf(r.out.c_str(), "hausdorff %lf (%*s of diagonal) rms %lf", &hausdorff, &rms),
            2)
      << r.out;
  EXPECT_GT(hausdorff, 0);
  EXPECT_GT(rms, 0);
  EXPECT_LE(rms, hausdorff);
  EXPECT_TRUE(test::file_exists(dir.file("c.obj")));
}

TEST(PmdecCompare, UsageAndReadErrors) {
  test::TempDir dir;
  const std::string original = test::sample_mesh_path("sphere.obj");
  ASSERT_EQ(run({original, "-o", dir.file("s.pm"), "-q"}, PMENC_PATH).exit_code, 0);
  // A missing ORIGINAL: one error line naming it, exit 3, and no output file.
  test::CommandResult r =
      run({dir.file("s.pm"), "--compare", dir.file("missing.obj"), "-o", dir.file("out.obj")},
          PMDEC_PATH);
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(r.err.rfind("pmdec: " + dir.file("missing.obj") + ": ", 0), 0u) << r.err;
  EXPECT_FALSE(test::file_exists(dir.file("out.obj")));
  EXPECT_EQ(r.out, "");
  // --json needs --compare; without --compare, an output is still required.
  EXPECT_EQ(run({dir.file("s.pm"), "--json", "-o", dir.file("out.obj")}, PMDEC_PATH).exit_code, 2);
  EXPECT_EQ(run({dir.file("s.pm")}, PMDEC_PATH).exit_code, 2);
  // The report goes to standard output, so the mesh cannot.
  EXPECT_EQ(run({dir.file("s.pm"), "--compare", original, "-o", "-"}, PMDEC_PATH).exit_code, 2);
}

}  // namespace
}  // namespace pm
