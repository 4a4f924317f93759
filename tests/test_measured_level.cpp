// Issue 3's acceptance for pmdec --error: the level returned measures at most E against the
// original, with no more than twice the faces of the coarsest level that measures at most E,
// found independently here by bisection over the levels.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/measured_level.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "pm/surface_distance.h"
#include "test_util.h"

namespace pm {
namespace {

double measured_hausdorff(const Mesh& original, const ProgressiveMesh& pm, std::size_t level) {
  SurfaceDistance d;
  const Status s = measure_surface_distance(original, extract_level(pm, level), {}, d);
  EXPECT_TRUE(s.is_ok()) << s.message();
  return d.hausdorff;
}

// The coarsest level measuring at most e, by plain bisection over level numbers (the test's
// own search, independent of the one under test).
std::size_t coarsest_by_bisection(const Mesh& original, const ProgressiveMesh& pm, double e) {
  std::size_t lo = 0, hi = pm.splits.size();
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (measured_hausdorff(original, pm, mid) <= e)
      hi = mid;
    else
      lo = mid + 1;
  }
  return lo;
}

struct Case {
  const char* file;
  Metric metric;
  double percent;
};

class MeasuredLevelOnRealMeshes : public ::testing::TestWithParam<Case> {};

TEST_P(MeasuredLevelOnRealMeshes, WithinToleranceAndWithinTwiceTheCoarsestFaces) {
  PM_SKIP_IF_NO_SHARED();
  const Case c = GetParam();
  Mesh original;
  ASSERT_TRUE(read_mesh(test::shared_mesh_path(c.file), original).is_ok());
  EncodeOptions options;
  options.metric = c.metric;
  ProgressiveMesh pm;
  ASSERT_TRUE(encode(original, options, pm).is_ok());
  const double e = c.percent / 100 * bounding_box_diagonal(original.positions);

  MeasuredLevel found;
  ASSERT_TRUE(level_for_measured_error(pm, e, {}, found).is_ok());
  // Measured again here, against the file itself rather than the stream's full detail.
  const double at_found = measured_hausdorff(original, pm, found.level);
  EXPECT_LE(at_found, e);
  // The same samples, up to rounding: the search measures against the stream's full detail,
  // the same surface as the file but with its own vertex order and corner rotations (the
  // encoder's split layers renumber vertices), so a sample's coordinates may differ in the
  // last bit.
  EXPECT_NEAR(at_found, found.distance.hausdorff, 1e-9 * e);
  EXPECT_LT(found.level, pm.splits.size());       // the tolerance is not met only by the input

  const std::size_t coarsest = coarsest_by_bisection(original, pm, e);
  EXPECT_LE(faces_at_level(pm, found.level), 2 * faces_at_level(pm, coarsest))
      << "found level " << found.level << ", bisection " << coarsest;
  std::printf("%s at %.2f%%: %zu faces after %zu measurements; bisection: %zu faces\n", c.file,
              c.percent, faces_at_level(pm, found.level), found.measurements,
              faces_at_level(pm, coarsest));
}

INSTANTIATE_TEST_SUITE_P(
    Issue3, MeasuredLevelOnRealMeshes,
    ::testing::Values(Case{"fandisk.obj", Metric::kSchroeder, 0.5},
                      Case{"fandisk.obj", Metric::kQuadric, 0.1},
                      Case{"stanford-bunny.obj", Metric::kSchroeder, 1.0},
                      Case{"stanford-bunny.obj", Metric::kQuadric, 0.25},
                      Case{"homer.obj", Metric::kQuadric, 2.0}),
    [](const ::testing::TestParamInfo<Case>& info) {
      std::string name = info.param.file;
      name = name.substr(0, name.find('.'));
      for (char& ch : name)
        if (ch == '-') ch = '_';
      return name + (info.param.metric == Metric::kQuadric ? "_quadric_" : "_schroeder_") +
             std::to_string(int(info.param.percent * 100)) + "cpct";
    });

// Under either metric the recorded error of a level bounds the distance from every input
// vertex to that level's surface (the removed points are tracked exactly). The bunny has
// holes, so boundary collapses that leave a point no replacing face are exercised too.
class RecordedError : public ::testing::TestWithParam<Metric> {};

TEST_P(RecordedError, BoundsEveryInputVertexDistance) {
  PM_SKIP_IF_NO_SHARED();
  Mesh original;
  ASSERT_TRUE(read_mesh(test::shared_mesh_path("stanford-bunny.obj"), original).is_ok());
  EncodeOptions options;
  options.metric = GetParam();
  ProgressiveMesh pm;
  ASSERT_TRUE(encode(original, options, pm).is_ok());
  // The input's vertices as a mesh of point-like faces: its samples are the vertices.
  // Vertices no face uses (the bunny has 1113) are not on the surface.
  std::vector<bool> used(original.vertex_count(), false);
  for (uint32_t v : original.triangles) used[v] = true;
  Mesh points;
  points.positions = original.positions;
  for (uint32_t v = 0; v < original.vertex_count(); ++v)
    if (used[v]) points.triangles.insert(points.triangles.end(), {v, v, v});
  DistanceOptions one_sample;
  one_sample.samples_per_face = 1;
  for (double fraction : {0.5, 0.1, 0.02, 0.005}) {
    const std::size_t level = level_for_faces(pm, std::size_t(fraction * original.face_count()));
    SurfaceDistance d;
    ASSERT_TRUE(measure_surface_distance(points, extract_level(pm, level), one_sample, d).is_ok());
    EXPECT_LE(d.forward_max, double(error_at_level(pm, level)) * (1 + 1e-6)) << fraction;
    EXPECT_GT(d.forward_max, 0) << fraction;
  }
}

INSTANTIATE_TEST_SUITE_P(Metrics, RecordedError,
                         ::testing::Values(Metric::kSchroeder, Metric::kQuadric),
                         [](const ::testing::TestParamInfo<Metric>& info) {
                           return info.param == Metric::kQuadric ? "quadric" : "schroeder";
                         });

// A literal square of two triangles: coarsening is impossible without changing the
// boundary, so every tolerance, even zero, gives a level that measures zero.
TEST(MeasuredLevel, ZeroToleranceIsMetByFullDetailOrAnExactLevel) {
  Mesh grid;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) grid.positions.insert(grid.positions.end(), {float(x), float(y), 0});
  for (uint32_t y = 0; y < 2; ++y) {
    for (uint32_t x = 0; x < 2; ++x) {
      const uint32_t v = 3 * y + x;
      grid.triangles.insert(grid.triangles.end(), {v, v + 1, v + 4, v, v + 4, v + 3});
    }
  }
  ProgressiveMesh pm;
  ASSERT_TRUE(encode(grid, {}, pm).is_ok());
  MeasuredLevel found;
  ASSERT_TRUE(level_for_measured_error(pm, 0.0, {}, found).is_ok());
  EXPECT_EQ(found.distance.hausdorff, 0.0);
  // A flat grid loses nothing by dropping its interior vertex and the mid-edge ones.
  EXPECT_LT(faces_at_level(pm, found.level), grid.face_count());
  EXPECT_EQ(measured_hausdorff(grid, pm, found.level), 0.0);
}

TEST(MeasuredLevel, RejectsBadArguments) {
  Mesh triangle;
  triangle.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  triangle.triangles = {0, 1, 2};
  ProgressiveMesh pm;
  ASSERT_TRUE(encode(triangle, {}, pm).is_ok());
  MeasuredLevel found;
  EXPECT_EQ(level_for_measured_error(pm, -1, {}, found).code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(level_for_measured_error(pm, 0.0 / 0.0, {}, found).code(),
            ErrorCode::kInvalidArgument);
  MeasuredLevelOptions options;
  options.face_ratio = 1;
  EXPECT_EQ(level_for_measured_error(pm, 1, options, found).code(), ErrorCode::kInvalidArgument);
  ProgressiveMesh broken = pm;
  broken.base_faces.push_back(99);
  EXPECT_EQ(level_for_measured_error(broken, 1, {}, found).code(), ErrorCode::kInvalidArgument);
}

// End to end: pmdec --error E (percent by default, model units with --absolute), checked
// with pmdec --compare --json, whose numbers are printed in full.
double compare_hausdorff(const std::string& pm_path, const std::vector<std::string>& level,
                         const std::string& original) {
  std::vector<std::string> args = {PMDEC_PATH, pm_path};
  args.insert(args.end(), level.begin(), level.end());
  args.insert(args.end(), {"--compare", original, "--json", "-q"});
  const test::CommandResult r = test::run_command(args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const std::size_t at = r.out.find("\"hausdorff\":");
  EXPECT_NE(at, std::string::npos) << r.out;
  return at == std::string::npos ? -1 : std::stod(r.out.substr(at + 12));
}

TEST(PmdecError, MeasuredHausdorffIsWithinTheToleranceInPercentOrModelUnits) {
  test::TempDir dir;
  const std::string original = test::sample_mesh_path("sphere.obj");
  ASSERT_EQ(test::run_command({PMENC_PATH, original, "-o", dir.file("s.pm"), "-q"}).exit_code, 0);
  Mesh sphere;
  ASSERT_TRUE(read_mesh(original, sphere).is_ok());
  const double diagonal = bounding_box_diagonal(sphere.positions);
  for (const char* tolerance : {"1", "0.3%"}) {
    const double hausdorff = compare_hausdorff(dir.file("s.pm"), {"--error", tolerance}, original);
    EXPECT_LE(hausdorff, std::stod(tolerance) / 100 * diagonal) << tolerance;
    EXPECT_GT(hausdorff, 0) << tolerance;  // a real simplification, not full detail
  }
  const double hausdorff =
      compare_hausdorff(dir.file("s.pm"), {"--error", "0.02", "--absolute"}, original);
  EXPECT_LE(hausdorff, 0.02);
  EXPECT_GT(hausdorff, 0);

  // A percent sign with --absolute is a contradiction; --absolute needs --error.
  const test::CommandResult bad = test::run_command(
      {PMDEC_PATH, dir.file("s.pm"), "--error", "1%", "--absolute", "-o", dir.file("x.obj")});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_FALSE(test::file_exists(dir.file("x.obj")));
  EXPECT_EQ(test::run_command({PMDEC_PATH, dir.file("s.pm"), "--absolute", "-o", dir.file("x.obj")})
                .exit_code,
            2);
}

TEST(PmdecError, EstimateSelectsByTheRecordedErrorsWithoutMeasuring) {
  test::TempDir dir;
  const std::string original = test::sample_mesh_path("sphere.obj");
  ASSERT_EQ(test::run_command({PMENC_PATH, original, "-o", dir.file("s.pm"), "-q"}).exit_code, 0);
  ProgressiveMesh pm;
  ASSERT_TRUE(read_pm(test::read_file(dir.file("s.pm")), pm).is_ok());
  const double diagonal = bounding_box_diagonal(pm.positions);
  const std::size_t level = level_for_error(pm, 0.01 * diagonal);
  const test::CommandResult r = test::run_command(
      {PMDEC_PATH, dir.file("s.pm"), "--error", "1", "--estimate", "-o", dir.file("e.obj")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("measured"), std::string::npos) << r.err;
  Mesh estimated;
  ASSERT_TRUE(read_mesh(dir.file("e.obj"), estimated).is_ok());
  EXPECT_EQ(estimated.face_count(), faces_at_level(pm, level));
}

}  // namespace
}  // namespace pm
