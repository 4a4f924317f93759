// glTF in and out (pm/gltf.h): a sample made here with every feature the reader decodes
// (two meshes, three materials, a node hierarchy with transforms, a UV seam, normals,
// colours, a quantized and a sparse accessor) read back to its world-space triangles; the
// writer's one level and chains read back bit for bit; hostile files refused cleanly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/gltf_glb.h"
#include "pm/encoder.h"
#include "pm/gltf.h"
#include "pm/lod.h"
#include "pm/mesh.h"
#include "pm/progressive_mesh.h"
#include "test_util.h"

namespace pm {
namespace {

using Json = nlohmann::json;

// A glTF under construction: its JSON and its one binary buffer.
struct GltfBuilder {
  Json document = {{"asset", {{"version", "2.0"}}}};
  std::string binary;

  // Appends raw values on a 4-byte boundary as a bufferView; returns its index.
  template <typename T>
  int view(const std::vector<T>& values, int stride = 0) {
    while (binary.size() % 4) binary.push_back('\0');
    Json v = {{"buffer", 0}, {"byteOffset", binary.size()}, {"byteLength", values.size() * sizeof(T)}};
    if (stride) v["byteStride"] = stride;
    binary.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
    document["bufferViews"].push_back(v);
    return static_cast<int>(document["bufferViews"].size() - 1);
  }
  int accessor(Json a) {
    document["accessors"].push_back(a);
    return static_cast<int>(document["accessors"].size() - 1);
  }
  std::string glb() {
    document["buffers"] = Json::array({{{"byteLength", binary.size()}}});
    return detail::make_glb(document.dump(), binary);
  }
};

constexpr int kFloat = 5126, kUnsignedByte = 5121, kUnsignedShort = 5123;

// The sample: node "root" (translation 1 2 3) with child "a" (a matrix turning x into y)
// showing mesh A, and node "b" (translation 10 0 0, scale 0.5) showing mesh B.
//  * mesh A: a 2 x 1 rectangle in two primitives (materials "red" and "green") that meet at
//    x = 1 with different texture coordinates there (a UV seam), float normals, colours as
//    normalized unsigned bytes (blue at the origin, red elsewhere).
//  * mesh B (material "blue"): a 4 x 4 square as unsigned shorts with a stride of 8
//    (KHR_mesh_quantization), its last vertex moved from z = 2 to z = 0 by a sparse accessor;
//    no normals, texture coordinates or colours.
std::string make_sample() {
  GltfBuilder b;
  auto& d = b.document;
  d["extensionsUsed"] = {"KHR_mesh_quantization"};
  d["extensionsRequired"] = {"KHR_mesh_quantization"};
  d["materials"] = {{{"name", "red"}}, {{"name", "green"}}, {{"name", "blue"}}};
  Json primitives = Json::array();
  for (int half = 0; half < 2; ++half) {
    const float x0 = float(half), x1 = float(half + 1), u0 = half ? 0.75f : 0.0f, u1 = half ? 1.0f : 0.5f;
    const std::vector<float> positions = {x0, 0, 0, x1, 0, 0, x1, 1, 0, x0, 1, 0};
    const std::vector<float> uvs = {u0, 0, u1, 0, u1, 1, u0, 1};
    const std::vector<float> normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    std::vector<uint8_t> colors;
    for (int v = 0; v < 4; ++v) {
      const bool origin = half == 0 && v == 0;
      for (uint8_t c : {origin ? 0 : 255, 0, origin ? 255 : 0, 255}) colors.push_back(c);
    }
    const std::vector<uint16_t> indices = {0, 1, 2, 0, 2, 3};
    Json attributes = {
        {"POSITION", b.accessor({{"bufferView", b.view(positions)}, {"componentType", kFloat}, {"count", 4},
                                 {"type", "VEC3"}, {"min", {x0, 0, 0}}, {"max", {x1, 1, 0}}})},
        {"TEXCOORD_0", b.accessor({{"bufferView", b.view(uvs)}, {"componentType", kFloat}, {"count", 4}, {"type", "VEC2"}})},
        {"NORMAL", b.accessor({{"bufferView", b.view(normals)}, {"componentType", kFloat}, {"count", 4}, {"type", "VEC3"}})},
        {"COLOR_0", b.accessor({{"bufferView", b.view(colors)}, {"componentType", kUnsignedByte}, {"normalized", true},
                                {"count", 4}, {"type", "VEC4"}})}};
    primitives.push_back({{"attributes", attributes},
                          {"indices", b.accessor({{"bufferView", b.view(indices)}, {"componentType", kUnsignedShort},
                                                  {"count", 6}, {"type", "SCALAR"}})},
                          {"material", half}});
  }
  d["meshes"].push_back({{"name", "A"}, {"primitives", primitives}});
  // Mesh B: x y z and 2 bytes of padding per vertex.
  const std::vector<uint16_t> square = {0, 0, 0, 0, 4, 0, 0, 0, 0, 4, 0, 0, 4, 4, 2, 0};
  const std::vector<uint8_t> sparse_indices = {3, 0, 0, 0};
  const std::vector<uint16_t> sparse_values = {4, 4, 0, 0};
  const int position = b.accessor(
      {{"bufferView", b.view(square, 8)}, {"componentType", kUnsignedShort}, {"count", 4}, {"type", "VEC3"},
       {"min", {0, 0, 0}}, {"max", {4, 4, 0}},
       {"sparse", {{"count", 1},
                   {"indices", {{"bufferView", b.view(sparse_indices)}, {"componentType", kUnsignedByte}}},
                   {"values", {{"bufferView", b.view(sparse_values)}}}}}});
  const std::vector<uint8_t> square_indices = {0, 1, 3, 0, 3, 2};
  d["meshes"].push_back(
      {{"name", "B"},
       {"primitives", {{{"attributes", {{"POSITION", position}}},
                        {"indices", b.accessor({{"bufferView", b.view(square_indices)}, {"componentType", kUnsignedByte},
                                                {"count", 6}, {"type", "SCALAR"}})},
                        {"material", 2}}}}});
  d["nodes"] = {{{"name", "root"}, {"translation", {1, 2, 3}}, {"children", {1}}},
                {{"name", "a"}, {"matrix", {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}, {"mesh", 0}},
                {{"name", "b"}, {"translation", {10, 0, 0}}, {"scale", {0.5, 0.5, 0.5}}, {"mesh", 1}}};
  d["scenes"] = {{{"nodes", {0, 2}}}};
  d["scene"] = 0;
  return b.glb();
}

// The sample's triangles in world space, written out by hand: one vertex per corner.
Mesh sample_world_triangles() {
  Mesh m;
  m.color_components = 4;
  m.material_names = {"red", "green", "blue"};
  auto corner = [&](float x, float y, float z, std::array<float, 4> rgba, const float* uv, bool normal) {
    m.triangles.push_back(static_cast<uint32_t>(m.vertex_count()));
    m.positions.insert(m.positions.end(), {x, y, z});
    m.colors.insert(m.colors.end(), rgba.begin(), rgba.end());
    m.uv_indices.push_back(uv ? static_cast<uint32_t>(m.uv_count()) : kNoAttribute);
    if (uv) m.uvs.insert(m.uvs.end(), {uv[0], uv[1]});
    m.normal_indices.push_back(normal ? static_cast<uint32_t>(m.normal_count()) : kNoAttribute);
    if (normal) m.normals.insert(m.normals.end(), {0, 0, 1});
  };
  // Mesh A under "a" under "root": (x, y, z) -> (1 - y, 2 + x, 3 + z).
  const std::array<float, 4> red = {1, 0, 0, 1}, blue = {0, 0, 1, 1}, white = {1, 1, 1, 1};
  for (int half = 0; half < 2; ++half) {
    const float x0 = float(half), x1 = float(half + 1), u0 = half ? 0.75f : 0.0f, u1 = half ? 1.0f : 0.5f;
    const float local[4][2] = {{x0, 0}, {x1, 0}, {x1, 1}, {x0, 1}};
    const float uv[4][2] = {{u0, 0}, {u1, 0}, {u1, 1}, {u0, 1}};
    for (int t : {0, 1, 2, 0, 2, 3}) {
      const bool origin = half == 0 && t == 0;
      corner(1 - local[t][1], 2 + local[t][0], 3, origin ? blue : red, uv[t], true);
    }
    m.face_materials.insert(m.face_materials.end(), {uint32_t(half), uint32_t(half)});
  }
  // Mesh B under "b": (x, y, z) -> (10 + x / 2, y / 2, z / 2), the sparse vertex at (4, 4, 0).
  const float square[4][2] = {{10, 0}, {12, 0}, {10, 2}, {12, 2}};
  for (int v : {0, 1, 3, 0, 3, 2}) corner(square[v][0], square[v][1], 0, white, nullptr, false);
  m.face_materials.insert(m.face_materials.end(), {2, 2});
  return m;
}

Mesh read_ok(const std::string& bytes, ReadReport* report = nullptr) {
  Mesh mesh;
  const Status s = read_gltf(bytes, {}, mesh, report);
  EXPECT_TRUE(s.is_ok()) << error_code_name(s.code()) << ": " << s.message();
  return mesh;
}

Status read_error(const std::string& bytes) {
  Mesh mesh;
  const Status s = read_gltf(bytes, {}, mesh);
  EXPECT_FALSE(s.is_ok()) << "read " << mesh.face_count() << " faces";
  EXPECT_FALSE(s.message().empty());
  EXPECT_EQ(s.message().find('\n'), std::string::npos) << s.message();
  return s;
}

Json json_of(const std::string& glb) {
  detail::GlbChunks chunks;
  EXPECT_TRUE(detail::split_glb(glb, chunks).is_ok());
  return Json::parse(chunks.json);
}

TEST(GltfRead, SampleGivesItsWorldSpaceTriangles) {
  ReadReport report;
  const Mesh mesh = read_ok(make_sample(), &report);
  EXPECT_TRUE(test::same_attributed_faces(sample_world_triangles(), mesh));
  // Mesh A's 8 glTF vertices are 6 points (the seam's two pairs weld); mesh B's 4 stay apart.
  EXPECT_EQ(mesh.vertex_count(), 10u);
  EXPECT_EQ(mesh.uv_count(), 8u);  // the seam's two texture coordinates per point stay
  EXPECT_EQ(report.vertices_given_default_color, 4u);
  EXPECT_TRUE(report.ignored_properties.empty());
}

TEST(GltfRead, GltfWithInlineBufferReadsAsTheGlb) {
  const std::string glb = make_sample();
  detail::GlbChunks chunks;
  ASSERT_TRUE(detail::split_glb(glb, chunks).is_ok());
  Json document = Json::parse(chunks.json);
  // The BIN chunk as a base64 data URI.
  static const char* kDigits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const std::string bin(chunks.binary.substr(0, document["buffers"][0]["byteLength"].get<std::size_t>()));
  std::string encoded;
  for (std::size_t i = 0; i < bin.size(); i += 3) {
    uint32_t v = uint32_t(uint8_t(bin[i])) << 16 | (i + 1 < bin.size() ? uint32_t(uint8_t(bin[i + 1])) << 8 : 0) |
                 (i + 2 < bin.size() ? uint8_t(bin[i + 2]) : 0);
    encoded += {kDigits[v >> 18 & 63], kDigits[v >> 12 & 63], i + 1 < bin.size() ? kDigits[v >> 6 & 63] : '=',
                i + 2 < bin.size() ? kDigits[v & 63] : '='};
  }
  document["buffers"][0]["uri"] = "data:application/octet-stream;base64," + encoded;
  EXPECT_TRUE(test::same_attributed_faces(sample_world_triangles(), read_ok(document.dump())));
}

TEST(GltfRead, ReportsWhatAMeshCannotHold) {
  GltfBuilder b;
  const std::vector<float> p = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const int position = b.accessor({{"bufferView", b.view(p)}, {"componentType", kFloat}, {"count", 3}, {"type", "VEC3"},
                                   {"min", {0, 0, 0}}, {"max", {1, 1, 0}}});
  const std::vector<float> t = {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1};
  const int tangent = b.accessor({{"bufferView", b.view(t)}, {"componentType", kFloat}, {"count", 3}, {"type", "VEC4"}});
  Json triangles = {{"attributes", {{"POSITION", position}, {"TANGENT", tangent}, {"TEXCOORD_1", position}}}};
  Json lines = {{"attributes", {{"POSITION", position}}}, {"mode", 1}};
  b.document["meshes"] = Json::array({{{"primitives", Json::array({triangles, lines})}}});
  b.document["nodes"] = {{{"mesh", 0}}};
  b.document["scenes"] = {{{"nodes", {0}}}, {{"nodes", {0}}}};
  ReadReport report;
  const Mesh mesh = read_ok(b.glb(), &report);
  EXPECT_EQ(mesh.face_count(), 1u);
  EXPECT_EQ(report.ignored_properties,
            (std::vector<std::string>{"TANGENT on 1 primitive", "TEXCOORD_1 on 1 primitive",
                                      "points and lines (pm holds triangles) on 1 primitive",
                                      "scenes other than the default on 1 file"}));
}

// A triangle whose POSITION accessor and primitive the test then edits.
GltfBuilder one_triangle() {
  GltfBuilder b;
  const std::vector<float> p = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::vector<uint16_t> i = {0, 1, 2, 0};
  const int position = b.accessor({{"bufferView", b.view(p)}, {"componentType", kFloat}, {"count", 3}, {"type", "VEC3"},
                                   {"min", {0, 0, 0}}, {"max", {1, 1, 0}}});
  const int indices = b.accessor({{"bufferView", b.view(i)}, {"componentType", kUnsignedShort}, {"count", 3}, {"type", "SCALAR"}});
  b.document["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", position}}}, {"indices", indices}}}}}};
  b.document["nodes"] = {{{"mesh", 0}}};
  b.document["scenes"] = {{{"nodes", {0}}}};
  return b;
}

TEST(GltfRead, OneTriangleReads) { EXPECT_EQ(read_ok(one_triangle().glb()).face_count(), 1u); }

TEST(GltfRead, MirroringNodeTurnsTrianglesOver) {
  GltfBuilder b = one_triangle();
  b.document["nodes"][0]["scale"] = {-1, 1, 1};
  const Mesh mesh = read_ok(b.glb());
  ASSERT_EQ(mesh.face_count(), 1u);
  // (0,0,0), (-1,0,0), (0,1,0) listed as (0, 2, 1): counter-clockwise seen from +z again.
  const float* a = &mesh.positions[3 * mesh.triangles[0]];
  const float* c1 = &mesh.positions[3 * mesh.triangles[1]];
  const float* c2 = &mesh.positions[3 * mesh.triangles[2]];
  const float cross_z = (c1[0] - a[0]) * (c2[1] - a[1]) - (c1[1] - a[1]) * (c2[0] - a[0]);
  EXPECT_GT(cross_z, 0);
}

TEST(GltfRead, HostileFilesAreRefusedCleanly) {
  EXPECT_EQ(read_error("{").code(), ErrorCode::kParseError);
  EXPECT_EQ(read_error("[]").code(), ErrorCode::kParseError);
  struct Case {
    const char* what;
    void (*edit)(Json&);
    ErrorCode code;
    const char* message;
  };
  const Case cases[] = {
      {"bufferView past its buffer", [](Json& d) { d["bufferViews"][0]["byteLength"] = 4000; }, ErrorCode::kParseError, ""},
      {"stride past the view", [](Json& d) { d["bufferViews"][0]["byteStride"] = 16; }, ErrorCode::kParseError, "end past"},
      {"accessor offset past the view", [](Json& d) { d["accessors"][0]["byteOffset"] = 32; }, ErrorCode::kParseError, "end past"},
      {"huge count", [](Json& d) { d["accessors"][0]["count"] = 4000000000u; }, ErrorCode::kResourceLimit, ""},
      {"huge count without data", [](Json& d) { d["accessors"][0].erase("bufferView"); d["accessors"][0]["count"] = 4000000000u; },
       ErrorCode::kResourceLimit, ""},
      {"missing accessor", [](Json& d) { d["meshes"][0]["primitives"][0]["indices"] = 9; }, ErrorCode::kParseError, ""},
      {"node cycle", [](Json& d) { d["nodes"][0]["children"] = {0}; }, ErrorCode::kParseError, "met twice"},
      {"missing scene node", [](Json& d) { d["scenes"][0]["nodes"] = {7}; }, ErrorCode::kParseError, "node 7"},
      {"draco required", [](Json& d) { d["extensionsUsed"] = {"KHR_draco_mesh_compression"}; d["extensionsRequired"] = {"KHR_draco_mesh_compression"}; },
       ErrorCode::kUnsupportedFormat, "KHR_draco_mesh_compression"},
      {"morph weights", [](Json& d) {
         d["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", 0}}};
         d["meshes"][0]["weights"] = {0.5};
       }, ErrorCode::kUnsupportedFormat, "morph targets"},
      {"non-unit matrix size", [](Json& d) { d["nodes"][0]["matrix"] = {1, 0, 0}; }, ErrorCode::kParseError, ""},
      // glTF 1.0 files are refused by their version, whether tinygltf loads them (a string)
      // or not (assimp's CesiumMilkTruck.gltf writes the number 1).
      {"glTF 1.0", [](Json& d) { d["asset"]["version"] = "1.0"; }, ErrorCode::kUnsupportedFormat,
       "glTF version 1.0 is not supported"},
      {"version as a number", [](Json& d) { d["asset"]["version"] = 1; }, ErrorCode::kUnsupportedFormat,
       "glTF version 1 is not supported"},
      // tinygltf's own words for these two are "asset object not found".
      {"asset without a version", [](Json& d) { d["asset"].erase("version"); }, ErrorCode::kParseError,
       "asset.version is missing"},
      {"no asset", [](Json& d) { d.erase("asset"); }, ErrorCode::kParseError, "asset"},
      // Draco's accessors have no bufferView (the data is in the extension's): tinygltf calls the
      // indices' invalid; the answer names the extension (assimp's 2CylinderEngine.gltf).
      {"draco required, accessors without data", [](Json& d) {
         d["extensionsUsed"] = {"KHR_draco_mesh_compression"};
         d["extensionsRequired"] = {"KHR_draco_mesh_compression"};
         for (Json& accessor : d["accessors"]) accessor.erase("bufferView");
       }, ErrorCode::kUnsupportedFormat, "required extension KHR_draco_mesh_compression is not supported"},
      {"points only", [](Json& d) { d["meshes"][0]["primitives"][0]["mode"] = 0; }, ErrorCode::kEmptyMesh,
       "no triangles in the default scene (it holds points and lines"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    GltfBuilder b = one_triangle();
    b.document["buffers"] = Json::array({{{"byteLength", b.binary.size()}}});
    c.edit(b.document);
    Mesh mesh;
    const std::string glb = detail::make_glb(b.document.dump(), b.binary);
    const Status s = read_gltf(glb, {}, mesh);
    EXPECT_EQ(s.code(), c.code) << s.message();
    EXPECT_NE(s.message().find(c.message), std::string::npos) << s.message();
  }
  // An index past the vertices.
  GltfBuilder b = one_triangle();
  b.binary[36 + 2] = 9;  // the second index (after the 36 bytes of positions): vertex 9 of 3
  EXPECT_NE(read_error(b.glb()).message().find("vertex 9 of 3"), std::string::npos);
}

TEST(GltfRead, GlbOfGltf1IsRefusedByName) {
  std::string glb = one_triangle().glb();
  glb[4] = 1;  // the header's version: binary glTF 1.0
  const Status s = read_error(glb);
  EXPECT_EQ(s.code(), ErrorCode::kUnsupportedFormat) << s.message();
  EXPECT_NE(s.message().find("glTF 1.0"), std::string::npos) << s.message();
  glb[4] = 3;  // no such version: malformed
  EXPECT_EQ(read_error(glb).code(), ErrorCode::kParseError);
}

TEST(GltfRead, EveryCutOfTheSampleIsACleanAnswer) {
  const std::string glb = make_sample();
  for (std::size_t n = 0; n < glb.size(); ++n) {
    Mesh mesh;
    const Status s = read_gltf(std::string_view(glb).substr(0, n), {}, mesh);
    ASSERT_FALSE(s.is_ok()) << "cut at " << n;
    ASSERT_NE(s.code(), ErrorCode::kInternal);
  }
  // A chunk length past the end is named as such.
  std::string cut = glb;
  cut[12] = static_cast<char>(0xF0);
  EXPECT_NE(read_error(cut).message().find("ends past"), std::string::npos);
}

TEST(GltfRead, ExternalBufferFromMemoryIsRefused) {
  GltfBuilder b = one_triangle();
  b.document["buffers"] = Json::array({{{"byteLength", b.binary.size()}, {"uri", "triangle.bin"}}});
  EXPECT_EQ(read_error(b.document.dump()).code(), ErrorCode::kParseError);
}

// ---------------------------------------------------------------------------------------
// Writing.

TEST(GltfWrite, OneLevelReadsBackBitForBit) {
  const Mesh grid = test::seamed_grid(6);
  for (bool binary : {true, false}) {
    SCOPED_TRACE(binary ? "glb" : "gltf");
    std::string bytes;
    GltfWriteOptions options;
    options.binary = binary;
    ASSERT_TRUE(write_gltf({{&grid, 0}}, options, bytes).is_ok());
    EXPECT_EQ(detail::is_glb(bytes), binary);
    const Mesh back = read_ok(bytes);
    EXPECT_TRUE(test::same_attributed_faces(grid, back));
    EXPECT_EQ(back.vertex_count(), grid.vertex_count());  // seams weld back
  }
}

TEST(GltfWrite, SampleThroughPmAndGlbGivesItsTriangles) {
  const Mesh sample = read_ok(make_sample());
  ProgressiveMesh progressive;
  ASSERT_TRUE(encode(sample, {}, progressive).is_ok());
  const Mesh full = extract_level(progressive, progressive.split_count());
  std::string glb;
  ASSERT_TRUE(write_gltf({{&full, 0}}, {}, glb).is_ok());
  EXPECT_TRUE(test::same_attributed_faces(sample_world_triangles(), read_ok(glb)));
}

TEST(GltfWrite, ChainSharesOneVertexBufferInSplitOrder) {
  const Mesh grid = test::seamed_grid(8);
  ProgressiveMesh progressive;
  ASSERT_TRUE(encode(grid, {}, progressive).is_ok());
  const std::vector<std::size_t> wanted = {level_for_faces(progressive, 20), level_for_faces(progressive, 60),
                                           progressive.split_count()};
  std::vector<Mesh> meshes;
  extract_levels(progressive, wanted, [&](std::size_t, const Mesh& m) { meshes.push_back(m); });
  ASSERT_EQ(meshes.size(), 3u);
  std::vector<GltfLevel> levels;
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    group_faces_by_material(meshes[i]);
    levels.push_back({&meshes[i], error_at_level(progressive, wanted[i])});
  }
  std::string glb;
  ASSERT_TRUE(write_gltf(levels, {}, glb).is_ok());
  const Json d = json_of(glb);
  EXPECT_EQ(d["extensionsUsed"], Json({"MSFT_lod"}));
  EXPECT_EQ(d["scenes"][0]["nodes"], Json({0}));
  EXPECT_EQ(d["nodes"][0]["extensions"]["MSFT_lod"]["ids"], Json({1, 2}));
  const Json& coverage = d["nodes"][0]["extras"]["MSFT_screencoverage"];
  ASSERT_EQ(coverage.size(), 3u);
  EXPECT_GE(coverage[0].get<double>(), coverage[1].get<double>());
  EXPECT_EQ(coverage[2].get<double>(), 0.0);
  // Every primitive of every level names the same POSITION accessor; a level's indices
  // name vertices below the count of the vertices its level and the coarser ones use.
  std::size_t used_before = 0;
  for (int n = 2; n >= 0; --n) {
    const Mesh& level = meshes[2 - n];
    std::size_t faces = 0, highest = 0;
    for (const Json& primitive : d["meshes"][n]["primitives"]) {
      EXPECT_EQ(primitive["attributes"]["POSITION"], 0);
      const Json& accessor = d["accessors"][primitive["indices"].get<int>()];
      faces += accessor["count"].get<std::size_t>() / 3;
      const Json& view = d["bufferViews"][accessor["bufferView"].get<int>()];
      detail::GlbChunks chunks;
      ASSERT_TRUE(detail::split_glb(glb, chunks).is_ok());
      const std::size_t start = view["byteOffset"].get<std::size_t>() + accessor["byteOffset"].get<std::size_t>();
      for (std::size_t i = 0; i < accessor["count"].get<std::size_t>(); ++i) {
        uint16_t index;
        std::memcpy(&index, chunks.binary.data() + start + 2 * i, 2);
        highest = std::max<std::size_t>(highest, index);
      }
    }
    EXPECT_EQ(faces, level.face_count());
    EXPECT_GE(highest + 1, used_before);  // each level adds vertices after the coarser ones'
    used_before = highest + 1;
    // One primitive per material (the grid's two) and nothing more.
    EXPECT_EQ(d["meshes"][n]["primitives"].size(), 2u);
  }
  EXPECT_EQ(d["accessors"][0]["count"].get<std::size_t>(), used_before);
  // A loader without MSFT_lod sees the finest level.
  EXPECT_TRUE(test::same_attributed_faces(meshes.back(), read_ok(glb)));
}

TEST(GltfWrite, QuantizedIsRequiredAndWithinTheGrid) {
  const Mesh grid = test::seamed_grid(6);
  std::string glb;
  GltfWriteOptions options;
  options.quantize = true;
  ASSERT_TRUE(write_gltf({{&grid, 0}}, options, glb).is_ok());
  const Json d = json_of(glb);
  EXPECT_EQ(d["extensionsRequired"], Json({"KHR_mesh_quantization"}));
  EXPECT_EQ(d["accessors"][0]["componentType"], kUnsignedShort);
  const double step = d["nodes"][0]["scale"][0].get<double>();
  const Mesh back = read_ok(glb);
  ASSERT_EQ(back.face_count(), grid.face_count());
  // Same faces in the same order (one primitive per material, in material order): compare
  // corner positions within half a grid step (and the float rounding of the transform).
  Mesh grouped = grid;
  group_faces_by_material(grouped);
  for (std::size_t c = 0; c < grouped.triangles.size(); ++c)
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(back.positions[3 * back.triangles[c] + i], grouped.positions[3 * grouped.triangles[c] + i],
                  step / 2 + 1e-6);
}

TEST(GltfWrite, MaterialSourceDefinitionsAreCopied) {
  GltfBuilder source = one_triangle();
  source.document["materials"] = {
      {{"name", "unused"}},
      {{"name", "stone"},
       {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0.25}}}}};
  source.document["textures"] = {{{"source", 0}, {"sampler", 0}}};
  source.document["samplers"] = {{{"magFilter", 9729}}};
  source.document["images"] = {{{"uri", "stone.png"}}};
  GltfMaterialSource materials{source.glb(), "textures"};
  Mesh triangle = read_ok(one_triangle().glb());
  triangle.material_names = {"stone", "plain"};
  triangle.face_materials = {0};
  Mesh second = triangle;
  second.face_materials = {1};
  GltfWriteOptions options;
  options.materials = &materials;
  std::string glb;
  ASSERT_TRUE(write_gltf({{&triangle, 1}, {&second, 0}}, options, glb).is_ok());
  const Json d = json_of(glb);
  EXPECT_EQ(d["materials"][0]["name"], "stone");
  EXPECT_EQ(d["materials"][0]["pbrMetallicRoughness"]["metallicFactor"], 0.25);
  EXPECT_EQ(d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"], 0);
  EXPECT_EQ(d["materials"][1], Json({{"name", "plain"}}));
  EXPECT_EQ(d["images"], Json({{{"uri", "textures/stone.png"}}}));
  EXPECT_EQ(d["samplers"][0]["magFilter"], 9729);
}

TEST(GltfWrite, RefusesWhatItCannotWrite) {
  std::string bytes;
  EXPECT_EQ(write_gltf({}, {}, bytes).code(), ErrorCode::kInvalidArgument);
  Mesh bad = test::seamed_grid(2);
  bad.positions[0] = std::nanf("");
  EXPECT_EQ(write_gltf({{&bad, 0}}, {}, bytes).code(), ErrorCode::kInvalidArgument);
}

TEST(GltfNames, FallBackToIndexWhenUnusableOrTaken) {
  GltfBuilder b = one_triangle();
  b.document["materials"] = {{{"name", "a"}}, {{"name", "a"}}, Json::object(), {{"name", "material_2"}},
                             {{"name", " x"}}};
  EXPECT_EQ(gltf_material_names(b.glb()),
            (std::vector<std::string>{"a", "material_1", "material_2_", "material_2", "material_4"}));
}

}  // namespace
}  // namespace pm
