// Attributes through the mesh readers and writers: vertex colours, per-corner texture
// coordinates and normals, per-face materials and material libraries, in OBJ, PLY and OFF.
// Small literal files with exact expectations, adversarial inputs, and round trips
// read -> write -> read that compare every face's corner values bit for bit.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "pm/mesh.h"
#include "pm/mesh_io.h"
#include "pm/status.h"
#include "test_util.h"

namespace pm {
namespace {

using std::string_literals::operator""s;
constexpr uint32_t kNone = kNoAttribute;

Mesh read_ok(const std::string& text, MeshFormat format = MeshFormat::kObj,
             ReadReport* report = nullptr) {
  Mesh mesh;
  Status status = read_mesh_from_memory(text, format, mesh, report);
  EXPECT_TRUE(status.is_ok()) << error_code_name(status.code()) << ": " << status.message();
  EXPECT_TRUE(test::ok(validate_attributes(mesh)));
  return mesh;
}

Status read_error(const std::string& text, MeshFormat format = MeshFormat::kObj) {
  Mesh mesh;
  Status status = read_mesh_from_memory(text, format, mesh);
  EXPECT_FALSE(status.is_ok()) << "unexpectedly read " << mesh.vertex_count() << " vertices, "
                               << mesh.face_count() << " faces";
  return status;
}

std::string write_ok(const Mesh& mesh, MeshFormat format) {
  std::string bytes;
  Status status = write_mesh_to_memory(mesh, format, bytes);
  EXPECT_TRUE(status.is_ok()) << error_code_name(status.code()) << ": " << status.message();
  return bytes;
}

uint32_t bits_of(float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

// Floats compared bit for bit.
::testing::AssertionResult same_floats(const std::vector<float>& expected,
                                       const std::vector<float>& actual) {
  if (expected.size() != actual.size()) {
    return ::testing::AssertionFailure()
           << "sizes differ: " << expected.size() << " vs " << actual.size();
  }
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (bits_of(expected[i]) != bits_of(actual[i])) {
      return ::testing::AssertionFailure()
             << "value " << i << ": expected " << expected[i] << ", got " << actual[i];
    }
  }
  return ::testing::AssertionSuccess();
}

// Everything a face carries, as bits: per corner its position, vertex colour, texture
// coordinate and normal (a marker for none), then the face's material name. Two meshes
// whose faces give equal records in the same order carry the same data, whatever their
// vertex numbering and value tables.
std::vector<std::string> face_records(const Mesh& mesh, bool with_materials = true) {
  std::vector<std::string> records;
  auto put_floats = [](std::string& out, const float* values, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) out += std::to_string(bits_of(values[i])) + ",";
  };
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    std::string record;
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t corner = 3 * f + k;
      const uint32_t v = mesh.triangles[corner];
      record += "p:";
      put_floats(record, &mesh.positions[3 * std::size_t{v}], 3);
      record += " c:";
      if (mesh.has_colors()) {
        put_floats(record, &mesh.colors[mesh.color_components * std::size_t{v}],
                   mesh.color_components);
      }
      record += " t:";
      const uint32_t uv = mesh.has_uvs() ? mesh.uv_indices[corner] : kNone;
      if (uv == kNone) {
        record += "none";
      } else {
        put_floats(record, &mesh.uvs[2 * std::size_t{uv}], 2);
      }
      record += " n:";
      const uint32_t normal = mesh.has_normals() ? mesh.normal_indices[corner] : kNone;
      if (normal == kNone) {
        record += "none";
      } else {
        put_floats(record, &mesh.normals[3 * std::size_t{normal}], 3);
      }
      record += " | ";
    }
    if (with_materials) {
      const uint32_t material = mesh.has_materials() ? mesh.face_materials[f] : kNone;
      record += "m:" + (material == kNone ? "none"s : mesh.material_names[material]);
    }
    records.push_back(record);
  }
  return records;
}

::testing::AssertionResult same_face_records(const Mesh& expected, const Mesh& actual,
                                             bool with_materials = true) {
  const std::vector<std::string> a = face_records(expected, with_materials);
  const std::vector<std::string> b = face_records(actual, with_materials);
  if (a.size() != b.size()) {
    return ::testing::AssertionFailure() << a.size() << " faces vs " << b.size();
  }
  for (std::size_t f = 0; f < a.size(); ++f) {
    if (a[f] != b[f]) {
      return ::testing::AssertionFailure()
             << "face " << f << " differs:\n  expected " << a[f] << "\n  actual   " << b[f];
    }
  }
  return ::testing::AssertionSuccess();
}

// A mesh with every kind of attribute and every awkward case: a UV seam and a normal seam
// at vertex 0, corners without a texture coordinate or a normal, a face with neither, faces
// without a material between faces with one, 4-component colours that are not k / 255, an
// unused material, and values that are not exactly decimal.
Mesh attribute_mesh() {
  Mesh mesh;
  mesh.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 0.5f, 1};
  mesh.triangles = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4, 0, 2, 1, 0, 3, 2};
  mesh.color_components = 4;
  mesh.colors = {0.1f, 0.2f, 0.3f,     1, 1, 0, 0,    0.5f, 0,    1,
                 0,    1,    1.0f / 3, 0, 0, 0, 0.7f, 0.7f, 0.7f, 0.25f};
  mesh.uvs = {0, 0, 1, 0, 1, 1, 0, 1, 0.5f, 0.5f, 1, 0.1f};
  mesh.uv_indices = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 5, 4, kNone, kNone, kNone, 0, kNone, 2};
  mesh.normals = {0, -1, 0.5f, 1, 0, 0.5f, 0, 1, 0.5f, -1, 0, 0.5f, 0, 0, -1, -0.0f, 1e-30f, 3};
  mesh.normal_indices = {0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4, 5, kNone, 4};
  mesh.material_names = {"red paint", "glass", "unused"};
  mesh.face_materials = {0, 0, kNone, 1, 1, kNone};
  mesh.material_libraries = {"scene.mtl", "more.mtl"};
  return mesh;
}

// ---------------------------------------------------------------------------------------
// OBJ reader
// ---------------------------------------------------------------------------------------

TEST(AttributeObjReader, ReadsTexturesNormalsColoursAndMaterials) {
  ReadReport report;
  const Mesh mesh = read_ok(
      "mtllib a.mtl b.mtl\n"
      "mtllib c.mtl\n"
      "v 0 0 0 1 0 0\n"
      "v 1 0 0 0 1 0\n"
      "v 0 1 0 0 0 1\n"
      "vt 0.25 0.5\n"
      "vt 1 0\n"
      "vt 0 1\n"
      "vn 0 0 1\n"
      "vn 0 0.5 2\n"
      "usemtl wood\n"
      "f 1/1/1 2/2/2 3/3/1\n"
      "usemtl Stone Wall # a comment\n"
      "f 3/3 2/2 1/1\n"
      "usemtl wood\n"
      "f 1//2 3//2 2//1\n",
      MeshFormat::kObj, &report);
  EXPECT_EQ(mesh.color_components, 3u);
  EXPECT_TRUE(same_floats({1, 0, 0, 0, 1, 0, 0, 0, 1}, mesh.colors));
  EXPECT_TRUE(same_floats({0.25f, 0.5f, 1, 0, 0, 1}, mesh.uvs));
  EXPECT_TRUE(same_floats({0, 0, 1, 0, 0.5f, 2}, mesh.normals));
  EXPECT_EQ(mesh.uv_indices, (std::vector<uint32_t>{0, 1, 2, 2, 1, 0, kNone, kNone, kNone}));
  EXPECT_EQ(mesh.normal_indices, (std::vector<uint32_t>{0, 1, 0, kNone, kNone, kNone, 1, 1, 0}));
  EXPECT_EQ(mesh.material_names, (std::vector<std::string>{"wood", "Stone Wall"}));
  EXPECT_EQ(mesh.face_materials, (std::vector<uint32_t>{0, 1, 0}));
  EXPECT_EQ(mesh.material_libraries, (std::vector<std::string>{"a.mtl", "b.mtl", "c.mtl"}));
  EXPECT_EQ(report.vertices_given_default_color, 0u);
  EXPECT_EQ(report.ignored_lines, 0u);
}

TEST(AttributeObjReader, MeshWithoutAttributesHasNone) {
  const Mesh mesh = read_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1 2 3\n");
  EXPECT_FALSE(mesh.has_colors());
  EXPECT_FALSE(mesh.has_uvs());
  EXPECT_FALSE(mesh.has_normals());
  EXPECT_FALSE(mesh.has_materials());
  // The tables are kept as read, even with no corner using them.
  EXPECT_EQ(mesh.uv_count(), 1u);
  EXPECT_EQ(mesh.normal_count(), 1u);
}

TEST(AttributeObjReader, CornersBeforeTheFirstAttributeHaveNone) {
  const Mesh mesh = read_ok(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 1\nvn 1 0 0\n"
      "f 1 2 3\n"
      "f 1/1 2 3/2\n"
      "f 1//1 2/2/1 3\n");
  EXPECT_EQ(mesh.uv_indices,
            (std::vector<uint32_t>{kNone, kNone, kNone, 0, kNone, 1, kNone, 1, kNone}));
  EXPECT_EQ(mesh.normal_indices,
            (std::vector<uint32_t>{kNone, kNone, kNone, kNone, kNone, kNone, 0, 0, kNone}));
}

TEST(AttributeObjReader, ResolvesNegativeAndForwardAttributeIndices) {
  const Mesh mesh = read_ok(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
      "vt 0 0\nvt 1 0\n"
      "vn 0 0 1\n"
      "f -3/-2/-1 -2/-1/-1 -1/-1/-1\n"  // vt 1 2 2, vn 1 1 1
      "vt 0 1\n"
      "vn 0 1 0\n"
      "f 1/-1/-2 2/-3/-1 3/4/2\n"  // vt 3 1 4 (forward), vn 1 2 2
      "vt 0.5 0.5\n");
  EXPECT_EQ(mesh.uv_indices, (std::vector<uint32_t>{0, 1, 1, 2, 0, 3}));
  EXPECT_EQ(mesh.normal_indices, (std::vector<uint32_t>{0, 0, 0, 0, 1, 1}));
}

TEST(AttributeObjReader, PolygonCornersAndMaterialFollowTheFan) {
  ReadReport report;
  const Mesh mesh = read_ok(
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0.5 0\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
      "vn 0 0 1\nvn 0 0 -1\n"
      "usemtl quad\n"
      "f 1/1/1 2/2/2 3/3/1 4/4/2\n"
      "usemtl pentagon\n"
      "f 5/5 1/1 2/2 3/3 4//2\n",
      MeshFormat::kObj, &report);
  EXPECT_EQ(report.polygons_triangulated, 2u);
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3,  // quad
                                                   4, 0, 1, 4, 1, 2, 4, 2, 3}));
  EXPECT_EQ(mesh.uv_indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3,  //
                                                    4, 0, 1, 4, 1, 2, 4, 2, kNone}));
  EXPECT_EQ(mesh.normal_indices,
            (std::vector<uint32_t>{0, 1, 0, 0, 0, 1,  //
                                   kNone, kNone, kNone, kNone, kNone, kNone, kNone, kNone, 1}));
  EXPECT_EQ(mesh.face_materials, (std::vector<uint32_t>{0, 0, 1, 1, 1}));
}

TEST(AttributeObjReader, MaterialsBeforeBetweenAndAfterFaces) {
  const Mesh mesh = read_ok(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
      "f 1 2 3\n"  // before any usemtl: none
      "usemtl a\n"
      "usemtl b\n"  // a is named but used by no face
      "f 1 2 3\n"
      "usemtl\n"  // no name: the following faces have none
      "f 1 2 3\n"
      "usemtl a\n"
      "f 1 2 3\n"
      "usemtl b\n"
      "f 1 2 3\n"
      "usemtl c\n");  // after the last face
  EXPECT_EQ(mesh.material_names, (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(mesh.face_materials, (std::vector<uint32_t>{kNone, 1, kNone, 0, 1}));
}

TEST(AttributeObjReader, ColoursOnSomeVerticesOnlyGetWhiteAndAreReported) {
  ReadReport report;
  Mesh mesh = read_ok(
      "v 0 0 0\n"
      "v 1 0 0 0.5 0.25 0.125\n"
      "v 0 1 0\n"
      "f 1 2 3\n",
      MeshFormat::kObj, &report);
  EXPECT_EQ(mesh.color_components, 3u);
  EXPECT_TRUE(same_floats({1, 1, 1, 0.5f, 0.25f, 0.125f, 1, 1, 1}, mesh.colors));
  EXPECT_EQ(report.vertices_given_default_color, 2u);

  // 3 and 4 components: alpha 1 for the 3-component colours, which is not a default.
  mesh = read_ok(
      "v 0 0 0 0.1 0.2 0.3\n"
      "v 1 0 0 0.4 0.5 0.6 0.7\n"
      "v 0 1 0\n"
      "f 1 2 3\n",
      MeshFormat::kObj, &report);
  EXPECT_EQ(mesh.color_components, 4u);
  EXPECT_TRUE(same_floats({0.1f, 0.2f, 0.3f, 1, 0.4f, 0.5f, 0.6f, 0.7f, 1, 1, 1, 1}, mesh.colors));
  EXPECT_EQ(report.vertices_given_default_color, 1u);
}

TEST(AttributeObjReader, ReportsValuesItCannotKeep) {
  ReadReport report;
  const Mesh mesh = read_ok(
      "v 1 2 3 1\n"    // w = 1: nothing lost
      "v 4 5 6 0.5\n"  // w dropped
      "v 7 8 9 2\n"    // w dropped
      "vt 0.5\n"       // v defaults to 0
      "vt 0.5 0.25 0\n"
      "vt 0.5 0.25 0.75\n"  // w dropped
      "f 1/1 2/2 3/3\n",
      MeshFormat::kObj, &report);
  EXPECT_FALSE(mesh.has_colors());
  EXPECT_TRUE(same_floats({1, 2, 3, 4, 5, 6, 7, 8, 9}, mesh.positions));
  EXPECT_TRUE(same_floats({0.5f, 0, 0.5f, 0.25f, 0.5f, 0.25f}, mesh.uvs));
  EXPECT_EQ(report.vertex_weights_dropped, 2u);
  EXPECT_EQ(report.texture_depths_dropped, 1u);
  const std::vector<std::string> lines = describe_read_report(report);
  EXPECT_EQ(lines, (std::vector<std::string>{"2 vertex weights w != 1 were not kept",
                                             "1 texture coordinate w != 0 was not kept"}));
}

TEST(AttributeObjReader, RejectsBadAttributeIndices) {
  const std::string head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 1\nvn 0 0 1\n";
  struct Case {
    std::string face;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"f 1/3 2/1 3/1", "line 7: texture coordinate index 3 out of range (2 texture coordinates)"},
      {"f 1/-3 2/1 3/1",
       "line 7: texture coordinate index -3 out of range (2 texture coordinates)"},
      {"f 1//2 2//1 3//1", "line 7: normal index 2 out of range (1 normals)"},
      {"f 1//-2 2//1 3//1", "line 7: normal index -2 out of range (1 normals)"},
      {"f 1/0 2/1 3/1", "line 7: texture coordinate index 0 is invalid (obj indices start at 1)"},
      {"f 1/1/0 2/1 3/1", "line 7: normal index 0 is invalid (obj indices start at 1)"},
      {"f 1/99999999999999999999 2 3", "line 7: texture coordinate index out of range"},
      {"f 1/1/1/1 2 3", "line 7: malformed face corner '1/1/1/1'"},
      {"f 1/a 2 3", "line 7: malformed face corner '1/a'"},
      {"f 1//1x 2 3", "line 7: malformed face corner '1//1x'"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.face);
    const Status status = read_error(head + c.face + "\n");
    EXPECT_EQ(status.code(), ErrorCode::kParseError);
    EXPECT_EQ(status.message(), c.message);
  }
  // A forward reference that never comes is named at its line; the earliest one wins.
  Status status = read_error(head + "f 1 2 3\nf 1//5 2 3\nf 1/7 2 3\nvt 0 0\n");
  EXPECT_EQ(status.message(), "line 8: normal index 5 out of range (1 normals)");
}

TEST(AttributeObjReader, RejectsMalformedAttributeStatements) {
  struct Case {
    std::string line;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"vt", "line 2: malformed texture coordinate"},
      {"vt a 0", "line 2: malformed texture coordinate"},
      {"vt 0 0 0 0", "line 2: malformed texture coordinate"},
      {"vt nan 0", "line 2: non-finite texture coordinate"},
      {"vt 0 1e39", "line 2: value out of float range"},
      {"vn 0 0", "line 2: malformed normal"},
      {"vn 0 0 1 0", "line 2: malformed normal"},
      {"vn 0 inf 1", "line 2: non-finite normal"},
      {"v 0 0 0 1 1", "line 2: malformed vertex"},
      {"v 0 0 0 1 nan 1", "line 2: non-finite colour"},
      {"v 0 0 0 red green blue", "line 2: malformed vertex"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.line);
    const Status status = read_error("v 0 0 0\n" + c.line + "\n");
    EXPECT_EQ(status.code(), ErrorCode::kParseError);
    EXPECT_EQ(status.message(), c.message);
  }
}

// ---------------------------------------------------------------------------------------
// OBJ writer
// ---------------------------------------------------------------------------------------

TEST(AttributeObjWriter, WritesEveryAttributeInItsShortestForm) {
  Mesh mesh;
  mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  mesh.triangles = {0, 1, 2, 2, 1, 0, 0, 2, 1, 1, 0, 2};
  mesh.color_components = 3;
  mesh.colors = {0.1f, 0.2f, 0.3f, 1, 1, 1, 0, 0, 0};
  mesh.uvs = {0.5f, 0.25f, 1.0f / 3, 1};
  mesh.uv_indices = {0, 1, 0, kNone, kNone, kNone, 1, kNone, 0, kNone, kNone, kNone};
  mesh.normals = {0, 0, 1, -0.0f, 1e-30f, 2};
  mesh.normal_indices = {0, 1, 0, 1, 1, 1, kNone, kNone, 0, kNone, kNone, kNone};
  mesh.material_names = {"a b", "c", "never used"};
  mesh.face_materials = {0, 0, kNone, 1};
  mesh.material_libraries = {"x.mtl", "y.mtl"};
  EXPECT_EQ(write_ok(mesh, MeshFormat::kObj),
            "mtllib x.mtl y.mtl\n"
            "v 0 0 0 0.1 0.2 0.3\n"
            "v 1 0 0 1 1 1\n"
            "v 0 1 0 0 0 0\n"
            "vt 0.5 0.25\n"
            "vt 0.33333334 1\n"
            "vn 0 0 1\n"
            "vn -0 1e-30 2\n"
            "usemtl a b\n"
            "f 1/1/1 2/2/2 3/1/1\n"
            "f 3//2 2//2 1//2\n"
            "usemtl\n"
            "f 1/2 3 2/1/1\n"
            "usemtl c\n"
            "f 2 1 3\n"
            "usemtl never used\n");
}

TEST(AttributeObjWriter, RejectsWhatCannotBeWrittenOrIsInvalid) {
  Mesh mesh;
  mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  mesh.triangles = {0, 1, 2};
  std::string bytes;
  for (const std::string& name : {"two\nlines"s, " padded"s, "padded "s, "#hash"s, "a #b"s, ""s}) {
    SCOPED_TRACE(name);
    Mesh named = mesh;
    named.material_names = {name};
    named.face_materials = {0};
    EXPECT_EQ(write_mesh_to_memory(named, MeshFormat::kObj, bytes).code(),
              ErrorCode::kInvalidArgument);
    EXPECT_EQ(write_mesh_to_memory(named, MeshFormat::kPly, bytes).code(),
              ErrorCode::kInvalidArgument);
  }
  Mesh library = mesh;
  library.material_libraries = {"my file.mtl"};  // would read back as two names
  EXPECT_EQ(write_mesh_to_memory(library, MeshFormat::kObj, bytes).code(),
            ErrorCode::kInvalidArgument);

  Mesh bad_index = mesh;
  bad_index.uvs = {0, 0};
  bad_index.uv_indices = {0, 1, 0};
  Status status = write_mesh_to_memory(bad_index, MeshFormat::kObj, bytes);
  EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(status.message(), "texture coordinate index 1 is 1, out of 1");

  Mesh not_finite = mesh;
  not_finite.normals = {0, std::numeric_limits<float>::quiet_NaN(), 1};
  not_finite.normal_indices = {0, 0, 0};
  for (MeshFormat format : {MeshFormat::kObj, MeshFormat::kPly, MeshFormat::kOff}) {
    status = write_mesh_to_memory(not_finite, format, bytes);
    EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument);
    EXPECT_EQ(status.message(), "a normal is not finite");
  }
}

// ---------------------------------------------------------------------------------------
// Round trips
// ---------------------------------------------------------------------------------------

TEST(AttributeRoundTrip, ObjKeepsTablesIndicesAndEveryValue) {
  const Mesh mesh = attribute_mesh();
  const Mesh back = read_ok(write_ok(mesh, MeshFormat::kObj));
  EXPECT_TRUE(same_floats(mesh.positions, back.positions));
  EXPECT_EQ(mesh.triangles, back.triangles);
  EXPECT_EQ(mesh.color_components, back.color_components);
  EXPECT_TRUE(same_floats(mesh.colors, back.colors));
  EXPECT_TRUE(same_floats(mesh.uvs, back.uvs));
  EXPECT_EQ(mesh.uv_indices, back.uv_indices);
  EXPECT_TRUE(same_floats(mesh.normals, back.normals));
  EXPECT_EQ(mesh.normal_indices, back.normal_indices);
  EXPECT_EQ(mesh.material_names, back.material_names);
  EXPECT_EQ(mesh.face_materials, back.face_materials);
  EXPECT_EQ(mesh.material_libraries, back.material_libraries);
  EXPECT_TRUE(same_face_records(mesh, back));
}

TEST(AttributeRoundTrip, PlyKeepsEveryCornerValue) {
  const Mesh mesh = attribute_mesh();
  const std::string bytes = write_ok(mesh, MeshFormat::kPly);
  // Float colours (not all k / 255), per-corner lists (seams and corners without), materials.
  const std::string header = bytes.substr(0, bytes.find("end_header\n"));
  EXPECT_NE(header.find("property float red\n"), std::string::npos) << header;
  EXPECT_NE(header.find("property float alpha\n"), std::string::npos) << header;
  EXPECT_NE(header.find("property list uchar float texcoord\n"), std::string::npos) << header;
  EXPECT_NE(header.find("property list uchar float corner_normals\n"), std::string::npos) << header;
  EXPECT_NE(header.find("comment pm_material red paint\n"), std::string::npos) << header;
  EXPECT_NE(header.find("comment pm_mtllib scene.mtl\n"), std::string::npos) << header;
  ReadReport report;
  const Mesh back = read_ok(bytes, MeshFormat::kPly, &report);
  EXPECT_TRUE(report.ignored_properties.empty());
  EXPECT_TRUE(same_floats(mesh.positions, back.positions));
  EXPECT_EQ(mesh.triangles, back.triangles);
  EXPECT_TRUE(same_floats(mesh.colors, back.colors));
  EXPECT_EQ(mesh.material_names, back.material_names);
  EXPECT_EQ(mesh.face_materials, back.face_materials);
  EXPECT_EQ(mesh.material_libraries, back.material_libraries);
  EXPECT_TRUE(same_face_records(mesh, back));
}

TEST(AttributeRoundTrip, MaterialNamesNoFaceUsesSurviveObjAndPly) {
  Mesh mesh;
  mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  mesh.triangles = {0, 1, 2};
  mesh.material_names = {"left over"};
  const Mesh from_obj = read_ok(write_ok(mesh, MeshFormat::kObj));
  EXPECT_EQ(from_obj.material_names, mesh.material_names);
  EXPECT_EQ(from_obj.face_materials, (std::vector<uint32_t>{kNone}));
  const Mesh from_ply = read_ok(write_ok(mesh, MeshFormat::kPly), MeshFormat::kPly);
  EXPECT_EQ(from_ply.material_names, mesh.material_names);
  EXPECT_FALSE(from_ply.has_materials());
}

TEST(AttributeRoundTrip, OffKeepsEveryCornerValueBySplittingSeams) {
  const Mesh mesh = attribute_mesh();
  const std::string text = write_ok(mesh, MeshFormat::kOff);
  EXPECT_EQ(text.substr(0, text.find('\n')), "STCNOFF");
  const Mesh back = read_ok(text, MeshFormat::kOff);
  // OFF has no materials; everything else survives, on split vertices.
  EXPECT_FALSE(back.has_materials());
  EXPECT_TRUE(same_face_records(mesh, back, /*with_materials=*/false));
  // One vertex per distinct (vertex, texture coordinate, normal) at the corners, counted here
  // independently of the writer.
  std::vector<std::array<uint32_t, 3>> keys;
  for (std::size_t c = 0; c < mesh.triangles.size(); ++c) {
    keys.push_back({mesh.triangles[c], mesh.uv_indices[c], mesh.normal_indices[c]});
  }
  std::sort(keys.begin(), keys.end());
  const auto expected_vertices =
      static_cast<std::size_t>(std::unique(keys.begin(), keys.end()) - keys.begin());
  EXPECT_EQ(back.vertex_count(), expected_vertices);
  EXPECT_GT(back.vertex_count(), mesh.vertex_count());
}

TEST(AttributeRoundTrip, PerVertexAttributesStayPerVertexInPlyAndOff) {
  // Every vertex has one texture coordinate and one normal; colours are bytes.
  Mesh mesh;
  mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  mesh.triangles = {0, 1, 2, 2, 1, 3};
  mesh.color_components = 3;
  mesh.colors = {1, 0, 0, 0, 1, 0, 0, 0, 1, 128 / 255.0f, 64 / 255.0f, 1 / 255.0f};
  mesh.uvs = {0, 0, 1, 0, 0, 1, 1, 1};
  mesh.uv_indices = mesh.triangles;
  mesh.normals = {0, 0, 1, 0, 0.5f, 1, 0, 0, 1, 0.25f, 0, 1};
  mesh.normal_indices = mesh.triangles;

  const std::string ply = write_ok(mesh, MeshFormat::kPly);
  const std::string header = ply.substr(0, ply.find("end_header\n") + 11);
  EXPECT_EQ(header,
            "ply\n"
            "format binary_little_endian 1.0\n"
            "element vertex 4\n"
            "property float x\nproperty float y\nproperty float z\n"
            "property uchar red\nproperty uchar green\nproperty uchar blue\n"
            "property float nx\nproperty float ny\nproperty float nz\n"
            "property float s\nproperty float t\n"
            "element face 2\n"
            "property list uchar int vertex_indices\n"
            "end_header\n");
  EXPECT_EQ(ply.size(), header.size() + 4 * (12 + 3 + 12 + 8) + 2 * 13);
  Mesh back = read_ok(ply, MeshFormat::kPly);
  EXPECT_TRUE(same_floats(mesh.colors, back.colors));
  EXPECT_EQ(back.uv_indices, mesh.triangles);
  EXPECT_EQ(back.normal_indices, mesh.triangles);
  EXPECT_TRUE(same_face_records(mesh, back));

  const std::string off = write_ok(mesh, MeshFormat::kOff);
  EXPECT_EQ(off,
            "STCNOFF\n4 2 0\n"
            "0 0 0 0 0 1 255 0 0 0 0\n"
            "1 0 0 0 0.5 1 0 255 0 1 0\n"
            "0 1 0 0 0 1 0 0 255 0 1\n"
            "1 1 0 0.25 0 1 128 64 1 1 1\n"
            "3 0 1 2\n"
            "3 2 1 3\n");
  back = read_ok(off, MeshFormat::kOff);
  EXPECT_EQ(back.vertex_count(), 4u);
  EXPECT_TRUE(same_face_records(mesh, back));
}

// Found by random damage: a vertex whose every corner has no normal must not come back with
// a zero normal from the per-vertex form.
TEST(AttributeRoundTrip, PerVertexNoneStaysNone) {
  Mesh mesh;
  mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 5};  // vertex 3 unused
  mesh.triangles = {0, 1, 2};
  mesh.normals = {0, 0, 1};
  mesh.normal_indices = {0, 0, kNone};
  mesh.uvs = {0.5f, 0.5f};
  mesh.uv_indices = {kNone, 0, 0};
  for (MeshFormat format : {MeshFormat::kPly, MeshFormat::kOff}) {
    SCOPED_TRACE(mesh_format_name(format));
    const Mesh back = read_ok(write_ok(mesh, format), format);
    EXPECT_EQ(back.vertex_count(), 4u);
    EXPECT_EQ(back.normal_indices, (std::vector<uint32_t>{0, 1, kNone}));
    EXPECT_EQ(back.uv_indices, (std::vector<uint32_t>{kNone, 1, 2}));
    EXPECT_TRUE(same_face_records(mesh, back));
  }
}

TEST(AttributeRoundTrip, FloatColoursInOffAreNeverTakenForBytes) {
  Mesh mesh;
  mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  mesh.triangles = {0, 1, 2};
  mesh.color_components = 3;
  mesh.colors = {1, 0, 0, 0, 1, 0, 0.3f, 0.6f, 0.9f};  // 0.3f is no k / 255
  const std::string off = write_ok(mesh, MeshFormat::kOff);
  EXPECT_EQ(off, "COFF\n3 1 0\n0 0 0 1.0 0.0 0.0\n1 0 0 0.0 1.0 0.0\n0 1 0 0.3 0.6 0.9\n3 0 1 2\n");
  EXPECT_TRUE(same_floats(mesh.colors, read_ok(off, MeshFormat::kOff).colors));
}

TEST(AttributeRoundTrip, SamplesAndSpotRoundTripExactly) {
  std::vector<std::string> paths = {test::sample_mesh_path("textured.obj"),
                                    test::sample_mesh_path("polygons.obj")};
  const bool shared = test::shared_meshes_available();
  if (shared) paths.push_back(test::shared_mesh_path("spot.obj"));
  for (const std::string& path : paths) {
    SCOPED_TRACE(path);
    Mesh mesh;
    ASSERT_TRUE(read_mesh(path, mesh).is_ok());
    ASSERT_TRUE(mesh.has_uvs());
    for (MeshFormat format : {MeshFormat::kObj, MeshFormat::kPly, MeshFormat::kOff}) {
      SCOPED_TRACE(mesh_format_name(format));
      const Mesh back = read_ok(write_ok(mesh, format), format);
      EXPECT_TRUE(same_face_records(mesh, back, format != MeshFormat::kOff));
      if (format != MeshFormat::kOff) {
        EXPECT_EQ(mesh.triangles, back.triangles);
        EXPECT_EQ(mesh.material_libraries, back.material_libraries);
      }
    }
  }
  PM_SKIP_IF_NO_SHARED();  // the samples ran; say loudly that spot did not
}

TEST(AttributeRoundTrip, TexturedSampleHasEveryAttribute) {
  Mesh mesh;
  ReadReport report;
  ASSERT_TRUE(read_mesh(test::sample_mesh_path("textured.obj"), mesh, &report).is_ok());
  EXPECT_EQ(mesh.color_components, 3u);
  EXPECT_EQ(report.vertices_given_default_color, 0u);
  EXPECT_EQ(mesh.material_names, (std::vector<std::string>{"body", "caps"}));
  EXPECT_EQ(mesh.material_libraries, (std::vector<std::string>{"textured.mtl"}));
  ASSERT_TRUE(mesh.has_uvs() && mesh.has_normals() && mesh.has_materials());
  // Seams: some vertex has corners with different texture coordinates, and some vertex has
  // corners with different normals.
  std::vector<uint32_t> uv_of(mesh.vertex_count(), kNone), normal_of(mesh.vertex_count(), kNone);
  std::size_t uv_seam_vertices = 0, normal_seam_vertices = 0;
  std::vector<bool> on_uv_seam(mesh.vertex_count()), on_normal_seam(mesh.vertex_count());
  for (std::size_t c = 0; c < mesh.triangles.size(); ++c) {
    const uint32_t v = mesh.triangles[c];
    ASSERT_NE(mesh.uv_indices[c], kNone);
    ASSERT_NE(mesh.normal_indices[c], kNone);
    if (uv_of[v] == kNone) uv_of[v] = mesh.uv_indices[c];
    if (normal_of[v] == kNone) normal_of[v] = mesh.normal_indices[c];
    if (uv_of[v] != mesh.uv_indices[c] && !on_uv_seam[v]) {
      on_uv_seam[v] = true;
      ++uv_seam_vertices;
    }
    if (normal_of[v] != mesh.normal_indices[c] && !on_normal_seam[v]) {
      on_normal_seam[v] = true;
      ++normal_seam_vertices;
    }
  }
  // Both rims (64 vertices each) are UV and normal seams; the body's cut adds its 25-2 other
  // vertices to the UV seams.
  EXPECT_EQ(normal_seam_vertices, 2u * 64);
  EXPECT_EQ(uv_seam_vertices, 2u * 64 + 23);
  std::size_t faces_per_material[2] = {0, 0};
  for (uint32_t material : mesh.face_materials) ++faces_per_material[material];
  EXPECT_EQ(faces_per_material[0], 24u * 64 * 2);
  EXPECT_EQ(faces_per_material[1], 2u * (2 * 64 * 2 + 64));
}

// ---------------------------------------------------------------------------------------
// PLY reader
// ---------------------------------------------------------------------------------------

TEST(AttributePlyReader, ReadsColoursNormalsAndTextureCoordinatesPerVertex) {
  ReadReport report;
  const Mesh mesh = read_ok(
      "ply\n"
      "format ascii 1.0\n"
      "element vertex 3\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty float ny\nproperty float nz\n"
      "property float texture_u\nproperty float texture_v\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
      "property float quality\n"
      "element face 1\n"
      "property list uchar int vertex_indices\n"
      "property uchar red\n"
      "element edge 1\n"
      "property int vertex1\nproperty int vertex2\n"
      "end_header\n"
      "0 0 0  0 0 1  0.25 0.5  255 0 0 255  7\n"
      "1 0 0  0 0.5 1  1 0  0 128 0 10  7\n"
      "0 1 0  0 0 1  0 1  0 0 1 0  7\n"
      "3 0 1 2 200\n"
      "0 1\n",
      MeshFormat::kPly, &report);
  EXPECT_EQ(mesh.color_components, 4u);
  EXPECT_TRUE(
      same_floats({1, 0, 0, 1, 0, 128 / 255.0f, 0, 10 / 255.0f, 0, 0, 1 / 255.0f, 0}, mesh.colors));
  EXPECT_TRUE(same_floats({0, 0, 1, 0, 0.5f, 1, 0, 0, 1}, mesh.normals));
  EXPECT_TRUE(same_floats({0.25f, 0.5f, 1, 0, 0, 1}, mesh.uvs));
  EXPECT_EQ(mesh.uv_indices, mesh.triangles);
  EXPECT_EQ(mesh.normal_indices, mesh.triangles);
  EXPECT_EQ(report.ignored_properties,
            (std::vector<std::string>{"vertex.quality", "face.red", "element edge"}));
}

TEST(AttributePlyReader, KeepsFloatColoursExactly) {
  // OpenMesh would truncate these to bytes: 0.3 * 255 = 76.5 -> 76 -> 0.298.
  const Mesh mesh = read_ok(
      "ply\nformat ascii 1.0\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property float red\nproperty float green\nproperty double blue\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0 0.3 0.1 0.7\n1 0 0 1 1 1\n0 1 0 0 0 0\n3 0 1 2\n",
      MeshFormat::kPly);
  EXPECT_EQ(mesh.color_components, 3u);
  EXPECT_TRUE(same_floats({0.3f, 0.1f, 0.7f, 1, 1, 1, 0, 0, 0}, mesh.colors));
}

TEST(AttributePlyReader, ReadsMeshLabTexcoordListsOnPolygons) {
  ReadReport report;
  const Mesh mesh = read_ok(
      "ply\nformat ascii 1.0\nelement vertex 4\n"
      "property float x\nproperty float y\nproperty float z\n"
      "element face 2\n"
      "property list uchar float texcoord\n"  // before vertex_indices: order is free
      "property list uchar int vertex_indices\n"
      "end_header\n"
      "0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
      "8 0 0 1 0 1 1 0 1 4 0 1 2 3\n"
      "0 3 0 2 3\n",  // no texture coordinates on this face
      MeshFormat::kPly, &report);
  EXPECT_EQ(report.polygons_triangulated, 1u);
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 0, 2, 3}));
  EXPECT_TRUE(same_floats({0, 0, 1, 0, 1, 1, 0, 1}, mesh.uvs));  // distinct values only
  EXPECT_EQ(mesh.uv_indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, kNone, kNone, kNone}));
}

TEST(AttributePlyReader, PerCornerListsWinOverPerVertexValues) {
  ReadReport report;
  const Mesh mesh = read_ok(
      "ply\nformat ascii 1.0\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\nproperty float u\nproperty float v\n"
      "element face 1\nproperty list uchar int vertex_indices\n"
      "property list uchar float texcoord\nend_header\n"
      "0 0 0 9 9\n1 0 0 9 9\n0 1 0 9 9\n3 0 1 2 6 0 0 1 0 0 1\n",
      MeshFormat::kPly, &report);
  EXPECT_TRUE(same_floats({0, 0, 1, 0, 0, 1}, mesh.uvs));
  EXPECT_EQ(report.ignored_properties, (std::vector<std::string>{"vertex.u", "vertex.v"}));
}

TEST(AttributePlyReader, IncompleteGroupsAndUnscaledTypesAreReported) {
  ReadReport report;
  const Mesh mesh = read_ok(
      "ply\nformat ascii 1.0\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\n"  // no blue
      "property float nx\nproperty float ny\n"      // no nz
      "property float s\n"                          // no t
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0 1 2 0 0 0\n1 0 0 1 2 0 0 0\n0 1 0 1 2 0 0 0\n3 0 1 2\n",
      MeshFormat::kPly, &report);
  EXPECT_FALSE(mesh.has_colors() || mesh.has_normals() || mesh.has_uvs());
  EXPECT_EQ(report.ignored_properties,
            (std::vector<std::string>{"vertex.red", "vertex.green", "vertex.nx", "vertex.ny",
                                      "vertex.s"}));
  // Colours of a type with no known scale (int) are reported, not guessed.
  read_ok(
      "ply\nformat ascii 1.0\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property int red\nproperty int green\nproperty int blue\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0 1 2 3\n1 0 0 1 2 3\n0 1 0 1 2 3\n3 0 1 2\n",
      MeshFormat::kPly, &report);
  EXPECT_EQ(report.ignored_properties,
            (std::vector<std::string>{"vertex.red", "vertex.green", "vertex.blue"}));
}

TEST(AttributePlyReader, ReadsBigEndianBinaryWithLists) {
  std::string bytes =
      "ply\nformat binary_big_endian 1.0\n"
      "comment pm_material  first one \n"
      "comment pm_material second\n"
      "element vertex 3\n"
      "property double x\nproperty double y\nproperty double z\n"
      "property ushort red\nproperty ushort green\nproperty ushort blue\n"
      "element face 2\n"
      "property list int uint vertex_indices\n"
      "property list ushort double texcoord\n"
      "property short pm_material\n"
      "end_header\n";
  auto put_be = [&bytes](uint64_t value, int size) {
    for (int i = size - 1; i >= 0; --i) bytes += static_cast<char>((value >> (8 * i)) & 0xff);
  };
  auto put_double = [&put_be](double value) {
    uint64_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    put_be(bits, 8);
  };
  const double positions[3][3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
  for (const auto& p : positions) {
    for (double c : p) put_double(c);
    for (int k = 0; k < 3; ++k) put_be(65535, 2);
  }
  put_be(3, 4);
  for (uint32_t v : {0u, 1u, 2u}) put_be(v, 4);
  put_be(6, 2);
  for (double t : {0.1, 0.2, 0.3, 0.4, 0.5, 0.6}) put_double(t);
  put_be(1, 2);
  put_be(3, 4);
  for (uint32_t v : {2u, 1u, 0u}) put_be(v, 4);
  put_be(0, 2);
  put_be(0xFFFF, 2);  // -1: no material
  const Mesh mesh = read_ok(bytes, MeshFormat::kPly);
  EXPECT_TRUE(same_floats({1, 1, 1, 1, 1, 1, 1, 1, 1}, mesh.colors));
  EXPECT_TRUE(same_floats({0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f}, mesh.uvs));
  EXPECT_EQ(mesh.uv_indices, (std::vector<uint32_t>{0, 1, 2, kNone, kNone, kNone}));
  EXPECT_EQ(mesh.material_names, (std::vector<std::string>{"first one", "second"}));
  EXPECT_EQ(mesh.face_materials, (std::vector<uint32_t>{1, kNone}));
}

TEST(AttributePlyReader, RejectsBadAttributeData) {
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty float ny\nproperty float nz\n"
      "element face 1\nproperty list uchar int vertex_indices\n"
      "property list uchar float texcoord\nproperty int pm_material\nend_header\n";
  const std::string vertices = "0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n";
  struct Case {
    std::string text;
    std::string message;
  };
  const std::vector<Case> cases = {
      {head + vertices + "3 0 1 2 4 0 0 1 0 -1\n", "face 0: texcoord has 4 values for 3 corners"},
      {head + vertices + "3 0 1 2 6 0 0 1 nan 0 1 -1\n", "face corner 1 has a non-finite texcoord"},
      {head + vertices + "3 0 1 2 6 0 0 1 0 inf 1 -1\n", "face corner 2 has a non-finite texcoord"},
      {head + vertices + "3 0 1 2 0 0\n", "face 0: pm_material 0 out of range (0 materials)"},
      {head + vertices + "3 0 1 2 0 -2\n", "face 0: pm_material -2 out of range (0 materials)"},
      {head + "0 0 0 0 0 1\n1 0 0 0 nan 1\n0 1 0 0 0 1\n3 0 1 2 0 -1\n",
       "vertex 1 has a non-finite normal"},
      {head + vertices + "3 0 1 2 0 1.5\n",
       "invalid ply file: truncated or malformed data in element face (item 0 of 1)"},
      {head + vertices + "3 0 1 2 6 0 0 1 0 0\n",
       "invalid ply file: truncated or malformed data in element face (item 0 of 1)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const Status status = read_error(c.text, MeshFormat::kPly);
    EXPECT_EQ(status.code(), ErrorCode::kParseError);
    EXPECT_EQ(status.message(), c.message);
  }
  // An all-NaN normal is a vertex without one.
  const Mesh mesh = read_ok(head + "0 0 0 0 0 1\n1 0 0 nan nan nan\n0 1 0 0 0 1\n3 0 1 2 0 -1\n",
                            MeshFormat::kPly);
  EXPECT_EQ(mesh.normal_indices, (std::vector<uint32_t>{0, kNone, 2}));
}

TEST(AttributePlyReader, DoublesRoundToFloatOrAreRejectedBeyondItsRange) {
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 1\n"
      "property double x\nproperty double y\nproperty double z\n"
      "property double nx\nproperty double ny\nproperty double nz\nend_header\n";
  // Above FLT_MAX by less than half its ulp (2^103): rounds to FLT_MAX.
  const Mesh mesh = read_ok(head + "3.40282356e38 0.1 -0 0 0 1e-50\n", MeshFormat::kPly);
  EXPECT_TRUE(same_floats({std::numeric_limits<float>::max(), 0.1f, -0.0f}, mesh.positions));
  EXPECT_TRUE(same_floats({0, 0, 0}, mesh.normals));
  // Exactly half an ulp above rounds to even, which is infinity.
  EXPECT_EQ(read_error(head + "3.4028235677973366e38 0 0 0 0 1\n", MeshFormat::kPly).message(),
            "vertex 0 has a non-finite coordinate");
  EXPECT_EQ(read_error(head + "1e300 0 0 0 0 1\n", MeshFormat::kPly).message(),
            "vertex 0 has a non-finite coordinate");
  EXPECT_EQ(read_error(head + "0 0 0 0 -1e39 1\n", MeshFormat::kPly).message(),
            "vertex 0 has a non-finite normal");
}

// ---------------------------------------------------------------------------------------
// OFF reader
// ---------------------------------------------------------------------------------------

TEST(AttributeOffReader, ReadsEachVariant) {
  const std::vector<uint32_t> triangle = {0, 1, 2};
  Mesh mesh =
      read_ok("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 1 0\n0 1 0 1 0 0\n3 0 1 2\n", MeshFormat::kOff);
  EXPECT_TRUE(same_floats({0, 0, 1, 0, 1, 0, 1, 0, 0}, mesh.normals));
  EXPECT_EQ(mesh.normal_indices, triangle);

  mesh = read_ok("COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 128\n0 1 0 0 0 255 0\n3 0 1 2\n",
                 MeshFormat::kOff);
  EXPECT_EQ(mesh.color_components, 4u);
  EXPECT_TRUE(same_floats({1, 0, 0, 1, 0, 1, 0, 128 / 255.0f, 0, 0, 1, 0}, mesh.colors));

  // Float colours, 3 and 4 components mixed: the 3-component one gets alpha 1.
  mesh = read_ok("COFF\n3 1 0\n0 0 0 1 0 0\n1 0 0 0 1 0 0.5\n0 1 0 0.25 0.25 1.\n3 0 1 2\n",
                 MeshFormat::kOff);
  EXPECT_EQ(mesh.color_components, 4u);
  EXPECT_TRUE(same_floats({1, 0, 0, 1, 0, 1, 0, 0.5f, 0.25f, 0.25f, 1, 1}, mesh.colors));

  mesh = read_ok("STOFF\n3 1 0\n0 0 0 0.5 0.25\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n", MeshFormat::kOff);
  EXPECT_TRUE(same_floats({0.5f, 0.25f, 1, 0, 0, 1}, mesh.uvs));
  EXPECT_EQ(mesh.uv_indices, triangle);

  // All three, in Geomview's order: normal, colour, texture coordinate.
  mesh = read_ok(
      "STCNOFF\n3 1 0\n0 0 0 0 0 1 9 9 9 0.5 0.5\n1 0 0 0 0 1 9 9 9 1 0\n0 1 0 0 0 1 9 9 9 0 1\n"
      "3 0 1 2\n",
      MeshFormat::kOff);
  EXPECT_TRUE(same_floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, mesh.normals));
  EXPECT_EQ(mesh.color_components, 3u);
  EXPECT_TRUE(same_floats(std::vector<float>(9, 9 / 255.0f), mesh.colors));
  EXPECT_TRUE(same_floats({0.5f, 0.5f, 1, 0, 0, 1}, mesh.uvs));

  mesh = read_ok(
      "CNOFF\n3 1\n0 0 0 0 0 1 0.5 0.5 0.5\n1 0 0 0 0 1 1 1 1\n0 1 0 0 0 1 0 0 0\n3 0 1 2\n",
      MeshFormat::kOff);
  EXPECT_TRUE(same_floats({0.5f, 0.5f, 0.5f, 1, 1, 1, 0, 0, 0}, mesh.colors));
}

TEST(AttributeOffReader, ReportsWhatItDoesNotKeep) {
  ReadReport report;
  const Mesh mesh = read_ok("OFF\n4 2 0\n0 0 0 7\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2 255 0 0\n3 1 3 2\n",
                            MeshFormat::kOff, &report);
  EXPECT_EQ(mesh.face_count(), 2u);
  EXPECT_FALSE(mesh.has_colors());
  EXPECT_EQ(report.ignored_properties,
            (std::vector<std::string>{"off vertex values beyond the header keyword's",
                                      "off face colours"}));
}

TEST(AttributeOffReader, RejectsBadAttributeValues) {
  struct Case {
    std::string text;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"COFF\n3 1 0\n0 0 0 1 0\n1 0 0 1 0 0\n0 1 0 1 0 0\n3 0 1 2\n", "line 3: malformed vertex"},
      {"COFF\n3 1 0\n0 0 0 1 0 0 0 0\n1 0 0 1 0 0\n0 1 0 1 0 0\n3 0 1 2\n",
       "line 3: malformed vertex"},
      {"NOFF\n3 1 0\n0 0 0 0 0\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n", "line 3: malformed vertex"},
      {"NOFF\n3 1 0\n0 0 0 0 nan 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n",
       "line 3: non-finite normal"},
      {"STOFF\n3 1 0\n0 0 0 inf 0\n1 0 0 0 0\n0 1 0 0 0\n3 0 1 2\n",
       "line 3: non-finite texture coordinate"},
      {"COFF\n3 1 0\n0 0 0 1 0 nan\n1 0 0 1 0 0\n0 1 0 1 0 0\n3 0 1 2\n",
       "line 3: non-finite colour"},
      {"COFF\n3 1 0\n0 0 0 256 0 0\n1 0 0 1 0 0\n0 1 0 1 0 0\n3 0 1 2\n",
       "vertex 0: integer colour component out of 0..255"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const Status status = read_error(c.text, MeshFormat::kOff);
    EXPECT_EQ(status.code(), ErrorCode::kParseError);
    EXPECT_EQ(status.message(), c.message);
  }
}

// ---------------------------------------------------------------------------------------
// Damaged files
// ---------------------------------------------------------------------------------------

// Whatever a reader accepts is a valid mesh, and writing it and reading it back gives the
// same corner values (what the fuzz targets check, here on attribute-rich files).
TEST(AttributeRobustness, DamagedFilesGiveAnErrorOrAValidMesh) {
  const Mesh mesh = attribute_mesh();
  std::mt19937 random(2024);
  for (MeshFormat format : {MeshFormat::kObj, MeshFormat::kPly, MeshFormat::kOff}) {
    SCOPED_TRACE(mesh_format_name(format));
    const std::string original = write_ok(mesh, format);
    int accepted = 0;
    for (int trial = 0; trial < 400; ++trial) {
      std::string damaged = original;
      const int edits = 1 + static_cast<int>(random() % 3);
      for (int e = 0; e < edits; ++e) {
        const std::size_t at = random() % damaged.size();
        switch (random() % 3) {
          case 0:
            damaged[at] = static_cast<char>(random());
            break;
          case 1:
            damaged.erase(at, 1 + random() % 4);
            break;
          default:
            damaged.insert(at, 1, "0123456789 -./\n#enavtfu"[random() % 24]);
            break;
        }
        if (damaged.empty()) damaged = "x";
      }
      Mesh result;
      const Status status = read_mesh_from_memory(damaged, format, result);
      if (!status.is_ok()) {
        ASSERT_FALSE(status.message().empty());
        continue;
      }
      ++accepted;
      std::string message;
      ASSERT_TRUE(test::ok(validate_attributes(result)));
      std::string written;
      const Status write = write_mesh_to_memory(result, format, written);
      if (!write.is_ok()) {
        // Only a name that cannot be written as it was read (e.g. with a control byte).
        ASSERT_EQ(write.code(), ErrorCode::kInvalidArgument) << write.message();
        continue;
      }
      Mesh back;
      ASSERT_TRUE(read_mesh_from_memory(written, format, back).is_ok());
      ASSERT_TRUE(same_face_records(result, back, format != MeshFormat::kOff));
    }
    EXPECT_GT(accepted, 0) << "no damaged file was readable: the test checks nothing";
  }
}

// ---------------------------------------------------------------------------------------
// STL: no attributes
// ---------------------------------------------------------------------------------------

TEST(AttributeStl, WritesGeometryOnly) {
  // STL has no place for attributes: the facet normal is derived from the corners, so a mesh
  // with attributes writes the same bytes as without them.
  Mesh mesh = attribute_mesh();
  const std::string with = write_ok(mesh, MeshFormat::kStl);
  Mesh plain;
  plain.positions = mesh.positions;
  plain.triangles = mesh.triangles;
  EXPECT_EQ(with, write_ok(plain, MeshFormat::kStl));
}

// group_faces_by_material: groups in the order of their first face, each stable, corners
// and their attributes moved with their faces, vertices untouched.
TEST(GroupFacesByMaterial, GroupsInFirstUseOrderStablyWithTheirCorners) {
  Mesh mesh;
  mesh.positions.assign(3 * 7, 0.0f);
  // Five faces: materials 1, 0, none, 1, 0.
  mesh.triangles = {0, 1, 2, 1, 2, 3, 2, 3, 4, 3, 4, 5, 4, 5, 6};
  mesh.uvs.assign(2 * 15, 0.0f);
  mesh.uv_indices = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14};
  mesh.normals.assign(3 * 15, 0.0f);
  mesh.normal_indices = {14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0};
  mesh.material_names = {"a", "b"};
  mesh.face_materials = {1, 0, kNoAttribute, 1, 0};
  const std::vector<float> positions = mesh.positions;
  group_faces_by_material(mesh);
  // Faces 0, 3 (b), then 1, 4 (a), then 2 (none).
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5, 1, 2, 3, 4, 5, 6, 2, 3, 4}));
  EXPECT_EQ(mesh.uv_indices,
            (std::vector<uint32_t>{0, 1, 2, 9, 10, 11, 3, 4, 5, 12, 13, 14, 6, 7, 8}));
  EXPECT_EQ(mesh.normal_indices,
            (std::vector<uint32_t>{14, 13, 12, 5, 4, 3, 11, 10, 9, 2, 1, 0, 8, 7, 6}));
  EXPECT_EQ(mesh.face_materials, (std::vector<uint32_t>{1, 1, 0, 0, kNoAttribute}));
  EXPECT_EQ(mesh.positions, positions);
  EXPECT_TRUE(test::ok(validate_attributes(mesh)));

  // Already grouped, one material, or none: unchanged.
  for (const std::vector<uint32_t>& materials :
       {std::vector<uint32_t>{1, 1, 0, 0, kNoAttribute}, std::vector<uint32_t>(5, 0),
        std::vector<uint32_t>{}}) {
    Mesh same = mesh;
    same.face_materials = materials;
    group_faces_by_material(same);
    EXPECT_EQ(same.triangles, mesh.triangles);
    EXPECT_EQ(same.uv_indices, mesh.uv_indices);
    EXPECT_EQ(same.face_materials, materials);
  }
}

}  // namespace
}  // namespace pm
