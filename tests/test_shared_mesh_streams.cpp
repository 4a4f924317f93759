// Every shared mesh's .pm, byte for byte: pmenc's stream of each mesh in ../shared/meshes,
// lossless and with --quantize 14, has the SHA-256 that tests/data/shared_mesh_streams.sha256
// records (written by pmenc before the codec was split into formats/v2/, issue 26: a move of
// the code must not change a byte). An encoder change that is meant to change the bytes
// regenerates the manifest with tests/shared_mesh_streams.sh. One test per mesh, so that
// ctest runs them side by side; CTest labels them `integration` (whole meshes through pmenc:
// tests/CMakeLists.txt), so that the sanitizer run leaves them out.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_util.h"

namespace pm {
namespace {

// One line of the manifest: "HASH  MESH [OPTIONS]".
struct RecordedStream {
  std::string hash;
  std::string mesh;
  std::vector<std::string> options;  // pmenc's, before -o
};

std::vector<RecordedStream> read_manifest() {
  const std::string path = std::string(PM_TEST_DATA_DIR) + "/shared_mesh_streams.sha256";
  std::ifstream in(path);
  std::vector<RecordedStream> streams;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream words(line);
    RecordedStream stream;
    words >> stream.hash >> stream.mesh;
    for (std::string option; words >> option;) stream.options.push_back(option);
    streams.push_back(stream);
  }
  return streams;
}

// The manifest's meshes, in its order, each once.
std::vector<std::string> manifest_meshes() {
  std::vector<std::string> meshes;
  for (const RecordedStream& stream : read_manifest()) {
    if (std::find(meshes.begin(), meshes.end(), stream.mesh) == meshes.end()) {
      meshes.push_back(stream.mesh);
    }
  }
  return meshes;
}

std::string sha256_of(const std::string& path) {
  const test::CommandResult result = test::run_command({"sha256sum", path});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  return result.out.substr(0, result.out.find(' '));
}

std::string command_text(const RecordedStream& stream) {
  std::string text = "pmenc " + stream.mesh;
  for (const std::string& option : stream.options) text += " " + option;
  return text;
}

class SharedMeshStreams : public testing::TestWithParam<std::string> {};

TEST_P(SharedMeshStreams, PmencWritesTheRecordedBytes) {
  PM_SKIP_IF_NO_SHARED();
  const std::string& mesh = GetParam();
  test::TempDir dir;
  for (const RecordedStream& stream : read_manifest()) {
    if (stream.mesh != mesh) continue;
    SCOPED_TRACE(command_text(stream));
    std::vector<std::string> argv = {PMENC_PATH, test::shared_mesh_path(mesh)};
    argv.insert(argv.end(), stream.options.begin(), stream.options.end());
    argv.insert(argv.end(), {"-o", dir.file("x.pm")});
    const test::CommandResult result = test::run_command(argv);
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_EQ(sha256_of(dir.file("x.pm")), stream.hash)
        << "the stream differs from the one recorded in tests/data/shared_mesh_streams.sha256; "
           "if the change is meant, regenerate it with tests/shared_mesh_streams.sh";
  }
}

// gtest names take letters, digits and underscores: "rocker-arm.obj" -> "rocker_arm_obj".
std::string test_name(const testing::TestParamInfo<std::string>& info) {
  std::string name = info.param;
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

INSTANTIATE_TEST_SUITE_P(EveryMesh, SharedMeshStreams, testing::ValuesIn(manifest_meshes()),
                         test_name);

// The manifest covers every shared mesh, lossless and at 14 bits, and nothing else: a mesh
// added to ../shared/meshes is noticed here.
TEST(SharedMeshStreamManifest, ListsEverySharedMeshLosslessAndAt14Bits) {
  PM_SKIP_IF_NO_SHARED();
  const std::vector<RecordedStream> streams = read_manifest();
  std::vector<std::string> expected, listed;
  for (const std::string& mesh : test::shared_mesh_names()) {
    expected.push_back(mesh);
    expected.push_back(mesh + " --quantize 14");
  }
  for (const RecordedStream& stream : streams) {
    EXPECT_EQ(stream.hash.size(), 64u) << command_text(stream);
    listed.push_back(command_text(stream).substr(6));  // less "pmenc "
  }
  EXPECT_EQ(listed, expected);
}

}  // namespace
}  // namespace pm
