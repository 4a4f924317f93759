// encode() on views (mesh_view.h): strided rows of the caller's arrays give the progressive
// mesh, and the stream, that encode() gives on the Mesh holding the same values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "pm/encoder.h"
#include "pm/mesh_view.h"
#include "pm/pm_codec.h"
#include "pm/version.h"
#include "test_util.h"

namespace pm {
namespace {

std::string stream_of(const ProgressiveMesh& pm) {
  std::string bytes;
  EXPECT_TRUE(test::ok(write_pm(pm, WriteOptions{}, bytes)));
  return bytes;
}

// An engine's layout: position and normal interleaved per vertex (6 floats), triangles padded
// to four indices, texture-coordinate and index tables packed.
TEST(MeshView, StridedViewsEncodeAsTheMeshDoes) {
  Mesh mesh = test::seamed_grid(8);  // rgb colours, texture coordinates, normals, materials
  ASSERT_EQ(mesh.color_components, 3u);
  mesh.material_libraries = {"grid.mtl"};
  ASSERT_TRUE(test::ok(validate_attributes(mesh)));

  std::vector<float> vertices;  // x y z r g b per vertex
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    vertices.insert(vertices.end(), &mesh.positions[3 * v], &mesh.positions[3 * v] + 3);
    vertices.insert(vertices.end(), &mesh.colors[3 * v], &mesh.colors[3 * v] + 3);
  }
  std::vector<uint32_t> padded;  // a b c and a pad per face
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    padded.insert(padded.end(), &mesh.triangles[3 * f], &mesh.triangles[3 * f] + 3);
    padded.push_back(0xDEADBEEFu);
  }
  MeshView view;
  view.positions = {vertices.data(), mesh.vertex_count(), 6 * sizeof(float)};
  view.colors = {vertices.data() + 3, mesh.vertex_count(), 6 * sizeof(float)};
  view.color_components = 3;
  view.triangles = {padded.data(), mesh.face_count(), 4 * sizeof(uint32_t)};
  view.uvs = {mesh.uvs.data(), mesh.uv_count(), 0};
  view.uv_indices = {mesh.uv_indices.data(), mesh.face_count(), 0};
  view.normals = {mesh.normals.data(), mesh.normal_count(), 0};
  view.normal_indices = {mesh.normal_indices.data(), mesh.face_count(), 0};
  view.face_materials = {mesh.face_materials.data(), mesh.face_count(), 0};
  view.material_names = &mesh.material_names;
  view.material_libraries = &mesh.material_libraries;

  ProgressiveMesh from_mesh, from_view;
  ASSERT_TRUE(test::ok(encode(mesh, EncodeOptions{}, from_mesh)));
  ASSERT_TRUE(test::ok(encode(view, EncodeOptions{}, from_view)));
  EXPECT_EQ(from_view.split_count(), from_mesh.split_count());
  EXPECT_EQ(stream_of(from_view), stream_of(from_mesh));
}

TEST(MeshView, MalformedViewsAreInvalidArguments) {
  const Mesh mesh = test::seamed_grid(2);
  MeshView view;
  view.positions = {mesh.positions.data(), mesh.vertex_count(), 0};
  view.triangles = {nullptr, mesh.face_count(), 0};
  ProgressiveMesh pm;
  Status status = encode(view, EncodeOptions{}, pm);
  EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(status.message(), "triangles: rows without data");
  view.triangles = {mesh.triangles.data(), mesh.face_count(), 2 * sizeof(uint32_t)};
  status = encode(view, EncodeOptions{}, pm);
  EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(status.message(), "triangles: stride shorter than a row");
  // Packed views of a mesh's own arrays: the mesh's checks apply as they are.
  view.triangles = {mesh.triangles.data(), mesh.face_count(), 0};
  std::vector<uint32_t> uv_indices = mesh.uv_indices;
  uv_indices[4] = static_cast<uint32_t>(mesh.uv_count());
  view.uvs = {mesh.uvs.data(), mesh.uv_count(), 0};
  view.uv_indices = {uv_indices.data(), mesh.face_count(), 0};
  status = encode(view, EncodeOptions{}, pm);
  EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(status.message().find("texture coordinate index 4"), std::string::npos)
      << status.message();
}

// pm::version() is the linked library's, the one the tools print.
TEST(Version, IsTheOneTheToolsPrint) {
  const std::string version = pm::version();
  EXPECT_EQ(version.find_first_not_of("0123456789."), std::string::npos) << version;
  EXPECT_EQ(std::count(version.begin(), version.end(), '.'), 2) << version;
  const test::CommandResult pmenc = test::run_command({PMENC_PATH, "--version"});
  ASSERT_EQ(pmenc.exit_code, 0) << pmenc.err;
  EXPECT_EQ(pmenc.out, "pmenc " + version + "\n");
}

}  // namespace
}  // namespace pm
