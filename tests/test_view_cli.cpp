// pmdec --view, --region and --viewpoint end to end: each writes the mesh the library gives
// for the same request; bad values are one-line usage errors (exit code 2) and write nothing.
#include <gtest/gtest.h>

#include <algorithm>

#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "pm/selective_refinement.h"
#include "test_util.h"

namespace pm {
namespace {

using test::CommandResult;
using test::run_command;
using test::TempDir;

CommandResult pmdec(std::vector<std::string> args) {
  args.insert(args.begin(), PMDEC_PATH);
  return run_command(args);
}

// sphere.obj encoded into dir/s.pm, and read back.
ProgressiveMesh encode_sample(const TempDir& dir) {
  const CommandResult enc =
      run_command({PMENC_PATH, test::sample_mesh_path("sphere.obj"), "-o", dir.file("s.pm"), "-q"});
  EXPECT_EQ(enc.exit_code, 0) << enc.err;
  ProgressiveMesh pm;
  EXPECT_TRUE(read_pm(test::read_file(dir.file("s.pm")), pm).ok());
  return pm;
}

Mesh read_or_fail(const std::string& path) {
  Mesh mesh;
  const Status s = read_mesh(path, mesh);
  EXPECT_TRUE(s.ok()) << path << ": " << s.message();
  return mesh;
}

TEST(ViewCli, ViewRegionAndViewpointWriteWhatTheLibraryGives) {
  TempDir dir;
  const ProgressiveMesh pm = encode_sample(dir);
  SelectiveRefinement r(pm);

  ViewCamera camera;
  camera.eye = {2.5, 0.5, 0.2};
  camera.target = {0, 0, 0};
  camera.up = {0, 0, 1};
  camera.fov_degrees = 40;
  camera.viewport_height = 300;
  ViewOptions options;
  options.pixel_error = 0.5;
  ASSERT_TRUE(r.set_view(camera, options).ok());
  CommandResult run = pmdec({dir.file("s.pm"), "--view",
                             "eye=2.5,0.5,0.2,target=0,0,0,up=0,0,1,fov=40,height=300",
                             "--pixel-error", "0.5", "-o", dir.file("v.obj")});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_GT(r.applied_count(), 0u);
  EXPECT_LT(r.applied_count(), r.split_count());
  EXPECT_TRUE(test::same_faces(r.to_mesh(), read_or_fail(dir.file("v.obj"))));
  // The summary line says what was applied.
  EXPECT_NE(run.err.find(std::to_string(r.applied_count()) + " of " +
                         std::to_string(r.split_count()) + " splits"),
            std::string::npos)
      << run.err;

  r.refine_sphere({0.5, 0.5, 0.5}, 0.4);
  run = pmdec({dir.file("s.pm"), "--region", "sphere:0.5,0.5,0.5,0.4", "-o", dir.file("r.obj"), "-q"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(test::same_faces(r.to_mesh(), read_or_fail(dir.file("r.obj"))));

  r.refine_box({-1, -1, 0}, {1, 1, 1});
  run = pmdec({dir.file("s.pm"), "--region", "box:-1,-1,0,1,1,1", "-o", dir.file("b.obj"), "-q"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(test::same_faces(r.to_mesh(), read_or_fail(dir.file("b.obj"))));

  ASSERT_TRUE(r.refine_toward({1, 0, 0}, 200, 0).ok());
  run = pmdec({dir.file("s.pm"), "--viewpoint", "1,0,0", "--faces", "200", "-o", dir.file("p.obj"), "-q"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Mesh budget = read_or_fail(dir.file("p.obj"));
  EXPECT_LE(budget.face_count(), 200u);
  EXPECT_TRUE(test::same_faces(r.to_mesh(), budget));

  ASSERT_TRUE(r.refine_toward({1, 0, 0}, 0, 90).ok());
  run = pmdec({dir.file("s.pm"), "--viewpoint", "1,0,0", "--vertices", "90", "-o", dir.file("q.obj"), "-q"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(test::same_faces(r.to_mesh(), read_or_fail(dir.file("q.obj"))));

  // --exact-ring: the stricter dependencies, and at least as many splits as the default.
  SelectiveRefinement exact(pm, DependencyRule::kExactRing);
  exact.refine_sphere({0.5, 0.5, 0.5}, 0.4);
  r.refine_sphere({0.5, 0.5, 0.5}, 0.4);
  EXPECT_GE(exact.applied_count(), r.applied_count());
  run = pmdec({dir.file("s.pm"), "--region", "sphere:0.5,0.5,0.5,0.4", "--exact-ring", "-o",
               dir.file("e.obj"), "-q"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(test::same_faces(exact.to_mesh(), read_or_fail(dir.file("e.obj"))));
}

TEST(ViewCli, BadValuesAreOneLineUsageErrors) {
  TempDir dir;
  encode_sample(dir);
  const std::string pm = dir.file("s.pm");
  const std::vector<std::vector<std::string>> cases = {
      {"--view", "eye=1,2,target=0,0,0,fov=60,height=100"},
      {"--view", "eye=1,2,3,target=0,0,0,fov=60"},
      {"--view", "eye=1,2,3,target=1,2,3,fov=60,height=100"},
      {"--view", "eye=1,2,3,target=0,0,0,fov=180,height=100"},
      {"--view", "eye=1,2,3,target=0,0,0,fov=60,height=0"},
      {"--view", "eye=1,2,3,target=0,0,0,up=1,2,3,fov=60,height=100"},
      {"--view", "eye=1,2,3,eye=1,2,3,target=0,0,0,fov=60,height=100"},
      {"--view", "fov=60"},
      {"--view", "eye=1,2,3,target=0,0,0,fov=60,height=100", "--pixel-error", "0"},
      {"--view", "eye=1,2,3,target=0,0,0,fov=60,height=100", "--pixel-error", "x"},
      {"--region", "sphere:0,0,0"},
      {"--region", "sphere:0,0,0,-1"},
      {"--region", "cube:0,0,0,1"},
      {"--region", "box:1,0,0,0,1,1"},
      {"--viewpoint", "1,0"},
      {"--viewpoint", "1,0,0"},
  };
  for (const auto& option : cases) {
    std::vector<std::string> args{pm};
    args.insert(args.end(), option.begin(), option.end());
    args.insert(args.end(), {"-o", dir.file("out.obj")});
    SCOPED_TRACE(option[1]);
    const CommandResult r = pmdec(args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    // The message names the offending option, the last of each case.
    EXPECT_EQ(r.err.rfind("pmdec: " + option[option.size() - 2], 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(test::file_exists(dir.file("out.obj")));
  }
  // A budget below the base mesh: the file and the problem, usage exit code.
  const CommandResult r = pmdec({pm, "--viewpoint", "0,0,0", "--faces", "1", "-o", dir.file("out.obj")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.rfind("pmdec: " + pm + ": budget of 1 faces", 0), 0u) << r.err;
  EXPECT_FALSE(test::file_exists(dir.file("out.obj")));
  // --exact-ring needs a selective mode.
  const CommandResult alone = pmdec({pm, "--exact-ring", "-o", dir.file("out.obj")});
  EXPECT_EQ(alone.exit_code, 2);
  EXPECT_EQ(alone.err, "pmdec: --exact-ring needs --view, --region or --viewpoint\n");
  EXPECT_FALSE(test::file_exists(dir.file("out.obj")));
  // The modes exclude each other and the level options.
  EXPECT_EQ(pmdec({pm, "--region", "sphere:0,0,0,1", "--ratio", "0.5", "-o", dir.file("out.obj")}).exit_code, 2);
  EXPECT_EQ(pmdec({pm, "--region", "sphere:0,0,0,1", "--viewpoint", "0,0,0", "--faces", "100", "-o",
                   dir.file("out.obj")})
                .exit_code,
            2);
}

}  // namespace
}  // namespace pm
