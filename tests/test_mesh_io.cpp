// Mesh input/output: the OBJ, PLY and OFF parsers, the OpenMesh-backed STL reader, the writers
// and format detection. Inputs are small literal files with exact expectations.

#include <gtest/gtest.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <algorithm>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "io/mesh_readers.h"
#include "pm/mesh.h"
#include "pm/mesh_io.h"
#include "pm/status.h"
#include "test_util.h"

namespace pm {
namespace {

using std::string_literals::operator""s;

// Reads `text` as `format`, expecting success.
Mesh read_ok(const std::string& text, MeshFormat format = MeshFormat::kObj,
             ReadReport* report = nullptr) {
  Mesh mesh;
  Status status = read_mesh_from_memory(text, format, mesh, report);
  EXPECT_TRUE(status.is_ok()) << error_code_name(status.code()) << ": " << status.message();
  return mesh;
}

bool same_bits(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Reads `text` as `format`, expecting failure.
Status read_error(const std::string& text, MeshFormat format = MeshFormat::kObj) {
  Mesh mesh;
  Status status = read_mesh_from_memory(text, format, mesh);
  EXPECT_FALSE(status.is_ok()) << "unexpectedly read " << mesh.vertex_count() << " vertices, "
                               << mesh.face_count() << " faces";
  EXPECT_FALSE(status.message().empty());
  return status;
}

uint32_t bits_of(float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

// Positions compared bit for bit (so -0 differs from +0), with a readable failure message.
::testing::AssertionResult same_positions(const std::vector<float>& expected,
                                          const std::vector<float>& actual) {
  if (expected.size() != actual.size()) {
    return ::testing::AssertionFailure()
           << "sizes differ: " << expected.size() << " vs " << actual.size();
  }
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (bits_of(expected[i]) != bits_of(actual[i])) {
      return ::testing::AssertionFailure() << "coordinate " << i << ": expected " << expected[i]
                                           << " (bits " << bits_of(expected[i]) << "), got "
                                           << actual[i] << " (bits " << bits_of(actual[i]) << ")";
    }
  }
  return ::testing::AssertionSuccess();
}

const std::string kTriangleObj =
    "v 0 0 0\n"
    "v 1 0 0\n"
    "v 0 1 0\n"
    "f 1 2 3\n";

// ---------------------------------------------------------------------------------------
// OBJ: accepted forms
// ---------------------------------------------------------------------------------------

TEST(ObjReader, ReadsTriangle) {
  ReadReport report;
  report.ignored_lines = 99;  // must be reset
  Mesh mesh = read_ok(kTriangleObj, MeshFormat::kObj, &report);
  EXPECT_TRUE(same_positions({0, 0, 0, 1, 0, 0, 0, 1, 0}, mesh.positions));
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(report.polygons_triangulated, 0u);
  EXPECT_EQ(report.ignored_lines, 0u);
}

TEST(ObjReader, AcceptsAllCornerForms) {
  const std::string text =
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
      "vt 0 0\nvt 1 0\nvt 0 1\n"
      "vn 0 0 1\nvn 0 0 1\nvn 0 0 1\n"
      "f 1 2 3\n"
      "f 1/1 2/2 3/3\n"
      "f 2//1 4//2 3//3\n"
      "f 1/2/3 2/3/1 3/1/2\n"
      "f 4/1/1 3//2 2/3\n";
  Mesh mesh = read_ok(text);
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 1, 2, 1, 3, 2, 0, 1, 2, 3, 2, 1}));
}

TEST(ObjReader, ResolvesNegativeIndicesAgainstVerticesSoFar) {
  const std::string text =
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
      "f -3 -2 -1\n"  // 2 3 4
      "v 2 2 2\n"
      "f -1 -5 -2\n"  // 5 1 4
      // Texture coordinate and normal indices must be in range too (test_attribute_io.cpp).
      "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nvn 0 1 0\n"
      "f -1/-1/-1 -2//-2 -3/-3\n";  // 5 4 3
  Mesh mesh = read_ok(text);
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{1, 2, 3, 4, 0, 3, 4, 3, 2}));
}

TEST(ObjReader, TriangulatesPolygonsAsFans) {
  ReadReport report;
  Mesh mesh = read_ok(
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0 0\n"
      "f 1 2 3 4\n",
      MeshFormat::kObj, &report);
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(report.polygons_triangulated, 1u);

  mesh = read_ok(
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0 0\nvt 0 0\n"
      "f 1 2 3\n"
      "f 1 2 3 4 5\n"
      "f 5/1 4/1 3/1 2/1\n",
      MeshFormat::kObj, &report);
  EXPECT_EQ(mesh.triangles,
            (std::vector<uint32_t>{0, 1, 2, 0, 1, 2, 0, 2, 3, 0, 3, 4, 4, 3, 2, 4, 2, 1}));
  EXPECT_EQ(report.polygons_triangulated, 2u);
}

TEST(ObjReader, SkipsCommentsBlankLinesAndCrLf) {
  const std::string text =
      "# a comment\r\n"
      "\r\n"
      "   \t \r\n"
      "v 0 0 0 # trailing comment\r\n"
      "\tv\t1 0 0\r\n"
      "v 0  1   0\r\n"
      "#f 9 9 9\r\n"
      "f 1 2 3#comment without a blank\r\n";
  ReadReport report;
  Mesh mesh = read_ok(text, MeshFormat::kObj, &report);
  EXPECT_TRUE(same_positions({0, 0, 0, 1, 0, 0, 0, 1, 0}, mesh.positions));
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(report.ignored_lines, 0u);
}

TEST(ObjReader, AcceptsMissingFinalNewlineAndByteOrderMark) {
  Mesh mesh = read_ok("\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3");
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(ObjReader, ToleratesGroupsMaterialsAndTextureStatementsWithoutCounting) {
  const std::string text =
      "mtllib scene.mtl\n"
      "o object name with spaces\n"
      "g group1 group2\n"
      "s off\n"
      "s 1\n"
      "usemtl Material.001\n"
      "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
      "vt 0.5 0.5\n"
      "vn 0 0 1\n"
      "f 1 2 3\n";
  ReadReport report;
  Mesh mesh = read_ok(text, MeshFormat::kObj, &report);
  EXPECT_EQ(mesh.face_count(), 1u);
  EXPECT_EQ(report.ignored_lines, 0u);
  EXPECT_EQ(report.polygons_triangulated, 0u);
}

TEST(ObjReader, CountsOtherStatementsAsIgnored) {
  const std::string text = kTriangleObj +
                           "l 1 2\n"
                           "p 3\n"
                           "vp 0.5 0.5\n"
                           "cstype bspline\n"
                           "deg 3\n"
                           "curv2 1 2\n"
                           "end\n"
                           "shadow_obj shadow.obj\n";
  ReadReport report;
  Mesh mesh = read_ok(text, MeshFormat::kObj, &report);
  EXPECT_EQ(mesh.face_count(), 1u);
  EXPECT_EQ(report.ignored_lines, 8u);
}

// Weights and colours themselves: test_attribute_io.cpp.
TEST(ObjReader, ReadsPositionsOfVerticesWithWeightOrColour) {
  Mesh mesh = read_ok(
      "v 1 2 3 1.0\n"
      "v 4 5 6 0.5 0.25 0.125\n"
      "v 7 8 9 1 0.5 0.25 0.125\n"
      "f 1 2 3\n");
  EXPECT_TRUE(same_positions({1, 2, 3, 4, 5, 6, 7, 8, 9}, mesh.positions));
}

TEST(ObjReader, ParsesNumberFormsExactly) {
  Mesh mesh = read_ok(
      "v +1 2. .5\n"
      "v 1e2 -2.5E-1 +3.1e+2\n"
      "v -0 0.1 1e-30\n"
      "v -3.4028235e38 123456.789 3.4028235e+38\n"
      "v 1e-45 1.17549435e-38 00012\n"
      "v 1e-50 -1e-60 0.30000001192092896\n");
  EXPECT_TRUE(
      same_positions({1.0f, 2.0f, 0.5f, 100.0f, -0.25f, 310.0f, -0.0f, 0.1f, 1e-30f, -3.4028235e38f,
                      123456.789f, 3.4028235e38f, 1e-45f, FLT_MIN, 12.0f, 0.0f, -0.0f, 0.3f},
                     mesh.positions));
}

// The readers' fast path for plain decimals (detail::parse_plain_decimal) must give what
// std::from_chars gives, bit for bit: random decimals of 1 to 19 digits with the point
// anywhere, many of them beyond what the fast path takes (it then declines).
TEST(TextNumbers, PlainDecimalsRoundAsFromChars) {
  std::mt19937_64 random(10);
  int fast = 0;
  for (int i = 0; i < 200000; ++i) {
    std::string text = random() % 2 ? "-" : "";
    const int digits = 1 + static_cast<int>(random() % 19);
    const int point = static_cast<int>(random() % static_cast<uint64_t>(digits + 1));
    for (int d = 0; d < digits; ++d) {
      if (d == point && d != 0) text += '.';
      text += static_cast<char>('0' + random() % 10);
    }
    SCOPED_TRACE(text);
    float expected = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), expected);
    ASSERT_EQ(error, std::errc());
    ASSERT_EQ(end, text.data() + text.size());
    const char* p = text.data();
    float value = -1;
    if (detail::parse_plain_decimal(p, text.data() + text.size(), value)) {
      ++fast;
      EXPECT_EQ(p, text.data() + text.size());
      EXPECT_TRUE(same_bits(value, expected)) << value << " != " << expected;
    }
    p = text.data();
    ASSERT_EQ(detail::parse_float(p, text.data() + text.size(), value), detail::NumberResult::kOk);
    EXPECT_TRUE(same_bits(value, expected)) << value << " != " << expected;
  }
  EXPECT_GT(fast, 100000);  // the fast path is what the test exercises
}

// Decimals whose nearest double lies exactly halfway between two floats, while they do not:
// rounding that double to float gives the wrong neighbour, so the fast path must decline
// them (found by searching midpoints of random floats).
TEST(TextNumbers, DecimalsNearlyHalfwayBetweenFloatsAreRoundedOnce) {
  const std::pair<std::string, float> cases[] = {{"0.596070796251297", 0x1.313032p-1f},
                                                 {"5.126182794570923", 0x1.481362p+2f},
                                                 {"30.99760341644287", 0x1.eff62ep+4f},
                                                 {"-30.99760341644287", -0x1.eff62ep+4f}};
  for (const auto& [text, expected] : cases) {
    SCOPED_TRACE(text);
    const double nearest = std::stod(text);
    EXPECT_NE(static_cast<float>(nearest), expected);  // what rounding twice would give
    const char* p = text.data();
    float value = 0;
    EXPECT_FALSE(detail::parse_plain_decimal(p, text.data() + text.size(), value));
    EXPECT_EQ(p, text.data());
    ASSERT_EQ(detail::parse_float(p, text.data() + text.size(), value), detail::NumberResult::kOk);
    EXPECT_TRUE(same_bits(value, expected));
  }
  Mesh mesh = read_ok("v 0.596070796251297 5.126182794570923 -30.99760341644287\n");
  EXPECT_TRUE(same_positions({0x1.313032p-1f, 0x1.481362p+2f, -0x1.eff62ep+4f}, mesh.positions));
}

// The search that found them, as a sweep: decimals of up to 16 digits near the midpoints of
// random floats.
TEST(TextNumbers, DecimalsNearFloatMidpointsRoundAsFromChars) {
  std::mt19937 random(10);
  std::uniform_real_distribution<float> significand(0.5f, 1.0f);
  for (int i = 0; i < 20000; ++i) {
    const float a = std::ldexp(significand(random), static_cast<int>(random() % 40) - 20);
    const double midpoint = (double{a} + double{std::nextafter(a, 2 * a)}) / 2;
    for (int decimals = 1; decimals <= 22; ++decimals) {
      char text[64];
      const int length = std::snprintf(text, sizeof text, "%.*f", decimals, midpoint);
      if (std::count_if(text, text + length, [](char c) { return c >= '0' && c <= '9'; }) > 16)
        break;
      float expected = 0, value = 0;
      std::from_chars(text, text + length, expected);
      const char* p = text;
      ASSERT_EQ(detail::parse_float(p, text + length, value), detail::NumberResult::kOk);
      ASSERT_TRUE(same_bits(value, expected)) << text;
    }
  }
}

// Face indices take a fast path for plain digits (up to 18 of them); signs, leading zeros
// and longer digit strings read as before.
TEST(ObjReader, ParsesIndexFormsExactly) {
  Mesh mesh = read_ok(kTriangleObj +
                      "f +1 000000000000000002 0000000000000000003\n"  // 18 and 19 digits
                      "f -3 -2/ -1//\n"
                      "f 3\t2 1 # 4\n");
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 1, 2, 0, 1, 2, 2, 1, 0}));
  Status status = read_error(kTriangleObj + "f 1 2 000000000000000000004\n");
  EXPECT_EQ(status.message(), "line 5: face index 4 out of range (3 vertices)");
  status = read_error(kTriangleObj + "f 1 2 4294967296\n");
  EXPECT_EQ(status.message(), "line 5: face index 4294967296 out of range (3 vertices)");
  status = read_error(kTriangleObj + "f 1 2 3-\n");
  EXPECT_EQ(status.message(), "line 5: malformed face corner '3-'");
}

// Plain triangles ("f a b c") take a fast path; around faces with attributes and
// materials they must get what any other face gets.
TEST(ObjReader, PlainTrianglesAmongAttributedFaces) {
  const uint32_t none = kNoAttribute;
  Mesh mesh = read_ok(kTriangleObj +
                      "vt 0 0\nvn 0 0 1\n"
                      "usemtl a\n"
                      "f 1 2 3 # plain\n"
                      "f 1/1 2/1 3/1\n"
                      "f 3 2 1\n"
                      "usemtl\n"
                      "f 1//1 2//1 3//1\n"
                      "f\t0000000003  2 1\t\n");
  // kTriangleObj's own face first.
  EXPECT_EQ(mesh.triangles,
            (std::vector<uint32_t>{0, 1, 2, 0, 1, 2, 0, 1, 2, 2, 1, 0, 0, 1, 2, 2, 1, 0}));
  EXPECT_EQ(mesh.uv_indices,
            (std::vector<uint32_t>{none, none, none, none, none, none, 0, 0, 0, none, none, none,
                                   none, none, none, none, none, none}));
  EXPECT_EQ(mesh.normal_indices,
            (std::vector<uint32_t>{none, none, none, none, none, none, none, none, none, none, none,
                                   none, 0, 0, 0, none, none, none}));
  EXPECT_EQ(mesh.face_materials, (std::vector<uint32_t>{none, 0, 0, 0, none, none}));
  // Indices a plain triangle cannot hold go the long way, to the same errors.
  EXPECT_EQ(read_error(kTriangleObj + "f 1 2 4294967296\n").message(),
            "line 5: face index 4294967296 out of range (3 vertices)");
  EXPECT_EQ(read_error(kTriangleObj + "f 1 2 44444444444444\n").message(),
            "line 5: face index 44444444444444 out of range (3 vertices)");
  EXPECT_EQ(read_error(kTriangleObj + "f 1 2 0\n").message(),
            "line 5: face index 0 is invalid (obj indices start at 1)");
  EXPECT_EQ(read_error(kTriangleObj + "f 1 2 3 x\n").message(),
            "line 5: malformed face corner 'x'");
  EXPECT_EQ(read_error("f 1 2 3\nf 1 2 4\nv 0 0 0\nv 0 0 0\nv 0 0 0\n").message(),
            "line 2: face index 4 out of range (3 vertices)");
}

// "v" and "f" lines are dispatched before their keyword is measured, and counted before
// parsing to reserve memory: lines that the count misses (the first, tab-separated,
// indented) and lines it may mistake must read as any others.
TEST(ObjReader, ReadsVertexAndFaceLinesInEveryLayout) {
  Mesh mesh = read_ok(
      "v\t0 0 0\n"
      "  v 1 0 0\r\n"
      "vt 0 0\n"
      "v 0 1 0\n"
      "# v 9 9 9\n"
      "\tf 1 2 3\n"
      "f\t1 3 2\r\n"
      "fo 1 2 3\n"
      "vx 1\n");
  EXPECT_TRUE(same_positions({0, 0, 0, 1, 0, 0, 0, 1, 0}, mesh.positions));
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 1}));
  EXPECT_EQ(mesh.uvs, (std::vector<float>{0, 0}));
  EXPECT_EQ(read_error("v 0 0 0\nv\n").message(), "line 2: malformed vertex");
  EXPECT_EQ(read_error("v 0 0 0\nf \n").message(), "line 2: face with fewer than 3 corners");
}

TEST(ObjReader, KeepsFacesWithRepeatedVertices) {
  Mesh mesh = read_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 2\nf 3 3 3\n");
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 0, 1, 2, 2, 2}));
}

TEST(ObjReader, ResolvesForwardReferences) {
  Mesh mesh = read_ok("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2}));
}

TEST(ObjReader, VerticesWithoutFacesAreAPointCloud) {
  Mesh mesh = read_ok("v 0 0 0\nv 1 0 0\n");
  EXPECT_EQ(mesh.vertex_count(), 2u);
  EXPECT_EQ(mesh.face_count(), 0u);
}

// ---------------------------------------------------------------------------------------
// OBJ: errors
// ---------------------------------------------------------------------------------------

TEST(ObjReader, RejectsFaceIndexBeyondVertices) {
  Status status = read_error(
      "# header\n"
      "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
      "f 1 2 4\n");
  EXPECT_EQ(status.code(), ErrorCode::kParseError);
  EXPECT_EQ(status.message(), "line 5: face index 4 out of range (3 vertices)");
}

TEST(ObjReader, RejectsNegativeIndexBeforeFirstVertex) {
  Status status = read_error("v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n");
  EXPECT_EQ(status.code(), ErrorCode::kParseError);
  EXPECT_EQ(status.message(), "line 3: face index -3 out of range (2 vertices)");
}

TEST(ObjReader, RejectsIndexZero) {
  Status status = read_error(kTriangleObj + "f 0 1 2\n");
  EXPECT_EQ(status.code(), ErrorCode::kParseError);
  EXPECT_NE(status.message().find("line 5:"), std::string::npos) << status.message();
  EXPECT_NE(status.message().find("index 0"), std::string::npos) << status.message();
}

TEST(ObjReader, RejectsHugeIndex) {
  Status status = read_error(kTriangleObj + "f 1 2 99999999999999999999999\n");
  EXPECT_EQ(status.code(), ErrorCode::kParseError);
  EXPECT_NE(status.message().find("line 5:"), std::string::npos) << status.message();
}

TEST(ObjReader, RejectsMalformedVertices) {
  for (const char* line : {"v 1 2", "v", "v 1 2 x", "v 1 2 3.1+e2", "v 1,5 2 3", "v 0x10 1 2",
                           "v 1 2 3 4 5 6 7 8", "v 1 2 3 red", "v 1 2 3e"}) {
    SCOPED_TRACE(line);
    Status status = read_error("v 0 0 0\n\n"s + line + "\n");
    EXPECT_EQ(status.code(), ErrorCode::kParseError);
    EXPECT_EQ(status.message(), "line 3: malformed vertex");
  }
}

TEST(ObjReader, RejectsNonFiniteCoordinates) {
  for (const char* line : {"v nan 0 0", "v 0 inf 0", "v 0 0 -inf", "v 0 0 infinity", "v NaN 1 2"}) {
    SCOPED_TRACE(line);
    Status status = read_error(kTriangleObj + line + "\n");
    EXPECT_EQ(status.code(), ErrorCode::kParseError);
    EXPECT_EQ(status.message(), "line 5: non-finite coordinate");
  }
}

TEST(ObjReader, RejectsCoordinateBeyondFloatRange) {
  Status status = read_error("v 1e39 0 0\n");
  EXPECT_EQ(status.code(), ErrorCode::kParseError);
  EXPECT_NE(status.message().find("line 1:"), std::string::npos) << status.message();
}

TEST(ObjReader, RejectsFacesWithFewerThanThreeCorners) {
  for (const char* line : {"f 1 2", "f 1", "f", "f # 1 2 3"}) {
    SCOPED_TRACE(line);
    Status status = read_error(kTriangleObj + "\n\n" + line + "\n");
    EXPECT_EQ(status.code(), ErrorCode::kParseError);
    EXPECT_EQ(status.message(), "line 7: face with fewer than 3 corners");
  }
}

TEST(ObjReader, RejectsMalformedCorners) {
  for (const char* line : {"f 1 2 a", "f 1/2/3/4 2 3", "f 1.5 2 3", "f 1/x 2 3", "f 1//y 2 3",
                           "f /1 2 3", "f 1 2 3,"}) {
    SCOPED_TRACE(line);
    Status status = read_error(kTriangleObj + line + "\n");
    EXPECT_EQ(status.code(), ErrorCode::kParseError);
    EXPECT_NE(status.message().find("line 5: malformed face corner"), std::string::npos)
        << status.message();
  }
}

TEST(ObjReader, RejectsNulBytes) {
  Status status = read_error(kTriangleObj + "f 1 2 3\n\0\0\0\0"s);
  EXPECT_EQ(status.code(), ErrorCode::kParseError);
  EXPECT_NE(status.message().find("line 6:"), std::string::npos) << status.message();
}

TEST(ObjReader, RejectsBinaryJunk) {
  // Bytes as found in compressed or image files: controls, and text that is no statement.
  Status status = read_error("v 0 0 0\n\x89PNG\r\n\x1a\n");
  EXPECT_EQ(status.code(), ErrorCode::kParseError);
  EXPECT_NE(status.message().find("line 3:"), std::string::npos) << status.message();

  status = read_error("v 0 0 0\n\xff\xfe\xfd\xfc binary\n");
  EXPECT_EQ(status.code(), ErrorCode::kParseError);
  EXPECT_EQ(status.message(), "line 2: not an obj statement");

  // A whole binary file, e.g. a PLY read as OBJ.
  Mesh triangle = read_ok(kTriangleObj);
  std::string ply;
  ASSERT_TRUE(write_mesh_to_memory(triangle, MeshFormat::kPly, ply).is_ok());
  EXPECT_EQ(read_error(ply).code(), ErrorCode::kParseError);
  std::string stl;
  ASSERT_TRUE(write_mesh_to_memory(triangle, MeshFormat::kStl, stl).is_ok());
  EXPECT_EQ(read_error(stl).code(), ErrorCode::kParseError);
}

TEST(ObjReader, EmptyInputIsAnEmptyMesh) {
  for (const std::string& text :
       {""s, "\n\n"s, "# only a comment\n"s, "  \r\n\t\n"s, "o name\ng group\n"s}) {
    SCOPED_TRACE(text);
    Status status = read_error(text);
    EXPECT_EQ(status.code(), ErrorCode::kEmptyMesh);
    EXPECT_EQ(status.message(), "no vertices or faces");
  }
}

TEST(ObjReader, LeavesMeshAndReportUntouchedOnError) {
  Mesh mesh = read_ok(kTriangleObj);
  ReadReport report;
  report.ignored_lines = 7;
  EXPECT_FALSE(
      read_mesh_from_memory("v 0 0 0\nl 1 2\nf 1 2\n", MeshFormat::kObj, mesh, &report).is_ok());
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(report.ignored_lines, 7u);
}

TEST(ObjReader, AgreesWithTheOracleOnSharedMeshes) {
  PM_SKIP_IF_NO_SHARED();
  for (const std::string& name : test::shared_mesh_names()) {
    if (mesh_format_from_path(name) != MeshFormat::kObj) continue;
    SCOPED_TRACE(name);
    Mesh mesh;
    Status status = read_mesh(test::shared_mesh_path(name), mesh);
    ASSERT_TRUE(status.is_ok()) << status.message();
    Mesh oracle = test::load_simple_obj(test::shared_mesh_path(name));
    EXPECT_TRUE(same_positions(oracle.positions, mesh.positions));
    EXPECT_EQ(oracle.triangles, mesh.triangles);
  }
}

// ---------------------------------------------------------------------------------------
// PLY and OFF (own parsers), STL through OpenMesh. Attributes: test_attribute_io.cpp
// ---------------------------------------------------------------------------------------

const std::string kAsciiPly =
    "ply\n"
    "format ascii 1.0\n"
    "comment made by hand\n"
    "element vertex 5\n"
    "property float x\n"
    "property float y\n"
    "property float z\n"
    "element face 2\n"
    "property list uchar int vertex_indices\n"
    "end_header\n"
    "0 0 0\n"
    "1 0 0\n"
    "1 1 0\n"
    "0 1 0\n"
    "0.1 1e-30 -3.4028235e38\n"
    "4 0 1 2 3\n"
    "3 4 0 2\n";

TEST(PlyReader, ReadsAsciiPly) {
  ReadReport report;
  Mesh mesh = read_ok(kAsciiPly, MeshFormat::kPly, &report);
  EXPECT_TRUE(same_positions({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.1f, 1e-30f, -3.4028235e38f},
                             mesh.positions));
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 4, 0, 2}));
  EXPECT_EQ(report.polygons_triangulated, 1u);
}

// A binary PLY as other tools write it: big-endian, double coordinates, extra properties,
// uint indices with an int count, another element before the faces.
std::string big_endian_ply() {
  std::string bytes =
      "ply\n"
      "format binary_big_endian 1.0\n"
      "element vertex 4\n"
      "property double x\n"
      "property double y\n"
      "property double z\n"
      "property uchar red\n"
      "element face 2\n"
      "property list int uint vertex_indices\n"
      "end_header\n";
  auto put_be = [&bytes](uint64_t value, int size) {
    for (int i = size - 1; i >= 0; --i) bytes += static_cast<char>((value >> (8 * i)) & 0xff);
  };
  auto put_double = [&put_be](double value) {
    uint64_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    put_be(bits, 8);
  };
  const double coordinates[4][3] = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.25, -0.5, 1e10}};
  for (const auto& vertex : coordinates) {
    for (double c : vertex) put_double(c);
    put_be(200, 1);
  }
  for (uint32_t index : {3u, 0u, 1u, 2u}) put_be(index, 4);
  for (uint32_t index : {4u, 0u, 1u, 3u, 2u}) put_be(index, 4);
  return bytes;
}

TEST(PlyReader, ReadsBinaryBigEndianPly) {
  ReadReport report;
  Mesh mesh = read_ok(big_endian_ply(), MeshFormat::kPly, &report);
  EXPECT_TRUE(same_positions({0, 0, 0, 2, 0, 0, 0, 2, 0, 0.25f, -0.5f, 1e10f}, mesh.positions));
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 1, 3, 0, 3, 2}));
  EXPECT_EQ(report.polygons_triangulated, 1u);
}

TEST(PlyReader, PlyErrors) {
  EXPECT_EQ(read_error("plyx garbage\n", MeshFormat::kPly).code(), ErrorCode::kParseError);
  EXPECT_EQ(read_error("not a ply file at all", MeshFormat::kPly).code(), ErrorCode::kParseError);
  EXPECT_EQ(read_error("", MeshFormat::kPly).code(), ErrorCode::kEmptyMesh);
  // Header without end_header.
  EXPECT_EQ(read_error("ply\nformat ascii 1.0\nelement vertex 3\n", MeshFormat::kPly).code(),
            ErrorCode::kParseError);

  // Out-of-range vertex index.
  std::string bad_index = kAsciiPly;
  bad_index.replace(bad_index.find("3 4 0 2"), 7, "3 4 0 9");
  Status status = read_error(bad_index, MeshFormat::kPly);
  EXPECT_EQ(status.code(), ErrorCode::kParseError);
  EXPECT_EQ(status.message(), "face 1 uses vertex 9 of 5");

  // Face with two corners.
  std::string short_face = kAsciiPly;
  short_face.replace(short_face.find("3 4 0 2"), 7, "2 4 0");
  EXPECT_EQ(read_error(short_face, MeshFormat::kPly).code(), ErrorCode::kParseError);

  // Non-numeric body.
  std::string garbage = kAsciiPly;
  garbage.replace(garbage.find("1 1 0"), 5, "a b c");
  EXPECT_EQ(read_error(garbage, MeshFormat::kPly).code(), ErrorCode::kParseError);

  // Non-finite coordinate.
  std::string nan_vertex = kAsciiPly;
  nan_vertex.replace(nan_vertex.find("1 1 0"), 5, "1 nan 0");
  EXPECT_EQ(read_error(nan_vertex, MeshFormat::kPly).code(), ErrorCode::kParseError);

  // Vertex-only PLY with no vertices.
  EXPECT_EQ(
      read_error("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                 "property float z\nend_header\n",
                 MeshFormat::kPly)
          .code(),
      ErrorCode::kEmptyMesh);
}

TEST(PlyReader, RejectsEveryTruncationOfPly) {
  // Every strict prefix that still contains the whole header lacks data the header promises.
  for (const std::string& full : {kAsciiPly, big_endian_ply()}) {
    const std::size_t body = full.find("end_header\n") + 11;
    for (std::size_t length = body; length + 1 < full.size(); ++length) {
      SCOPED_TRACE(length);
      Mesh mesh;
      Status status = read_mesh_from_memory(full.substr(0, length), MeshFormat::kPly, mesh);
      EXPECT_FALSE(status.is_ok())
          << "read " << mesh.vertex_count() << " vertices, " << mesh.face_count() << " faces";
    }
  }
}

// A binary PLY as our writer makes it: float x y z, faces as uchar count and int indices.
std::string little_endian_ply(const std::vector<std::vector<float>>& vertices,
                              const std::vector<std::vector<int32_t>>& faces) {
  std::string bytes =
      "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(vertices.size()) +
      "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
      std::to_string(faces.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  auto put = [&bytes](const void* value, std::size_t size) {
    for (std::size_t i = 0; i < size; ++i) bytes += static_cast<const char*>(value)[i];
  };
  for (const std::vector<float>& vertex : vertices) {
    for (float c : vertex) put(&c, 4);  // the tests run on little-endian hosts
  }
  for (const std::vector<int32_t>& face : faces) {
    bytes += static_cast<char>(face.size());
    for (int32_t index : face) put(&index, 4);
  }
  return bytes;
}

// Binary vertex and face elements in the common layouts are read item by item, not value
// by value; the errors must name the same item the value-by-value loop names. Every cut of
// the data falls in some item: a truncation of it, or, once a face's count is whole, a list
// longer than the bytes left (each value takes at least one).
TEST(PlyReader, BinaryTruncationNamesTheItem) {
  struct Layout {
    std::string bytes;
    std::size_t vertex_size, vertices;
    std::size_t count_size, index_size;
    std::vector<std::size_t> corners;  // per face
  };
  const Layout layouts[] = {
      {little_endian_ply({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}, {{0, 1, 2}, {1, 3, 2, 0}}),
       12,
       4,
       1,
       4,
       {3, 4}},
      {big_endian_ply(), 25, 4, 4, 4, {3, 4}}};
  for (const Layout& layout : layouts) {
    const std::size_t body = layout.bytes.find("end_header\n") + 11;
    ASSERT_EQ(layout.bytes.size(), body + layout.vertex_size * layout.vertices +
                                       2 * layout.count_size + 7 * layout.index_size);
    for (std::size_t length = body; length < layout.bytes.size(); ++length) {
      SCOPED_TRACE(length);
      std::size_t offset = length - body;
      std::string expected;
      if (offset < layout.vertex_size * layout.vertices) {
        expected = "truncated or malformed data in element vertex (item " +
                   std::to_string(offset / layout.vertex_size) + " of 4)";
      } else {
        offset -= layout.vertex_size * layout.vertices;
        std::size_t item = 0;
        while (offset >= layout.count_size + layout.corners[item] * layout.index_size) {
          offset -= layout.count_size + layout.corners[item] * layout.index_size;
          ++item;
        }
        if (offset >= layout.count_size && layout.corners[item] > offset - layout.count_size)
          expected = "element face item " + std::to_string(item) + ": bad list length";
        else
          expected = "truncated or malformed data in element face (item " + std::to_string(item) +
                     " of 2)";
      }
      EXPECT_EQ(read_error(layout.bytes.substr(0, length), MeshFormat::kPly).message(),
                "invalid ply file: " + expected);
    }
  }
}

TEST(PlyReader, BinaryItemErrorsNameTheItem) {
  const std::vector<std::vector<float>> vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(read_error(little_endian_ply({{0, 0, 0}, {1, nan, 0}, {0, 1, 0}}, {{0, 1, 2}}),
                       MeshFormat::kPly)
                .message(),
            "vertex 1 has a non-finite coordinate");
  EXPECT_EQ(
      read_error(little_endian_ply(vertices, {{0, 1, 2}, {0, 1}}), MeshFormat::kPly).message(),
      "invalid ply file: face 1 has fewer than 3 corners");
  EXPECT_EQ(
      read_error(little_endian_ply(vertices, {{0, 1, 2}, {0, 1, 3}}), MeshFormat::kPly).message(),
      "face 1 uses vertex 3 of 3");
  EXPECT_EQ(
      read_error(little_endian_ply(vertices, {{0, 1, 2}, {0, -1, 2}}), MeshFormat::kPly).message(),
      "face 1 uses vertex -1 of 3");
  // Indices are kept in 32 bits; a negative one is kept aside, and reported as it was.
  EXPECT_EQ(
      read_error(little_endian_ply(vertices, {{0, -7, 2}, {0, 1, 5}}), MeshFormat::kPly).message(),
      "face 0 uses vertex -7 of 3");
  EXPECT_EQ(
      read_error(little_endian_ply(vertices, {{0, 1, 5}, {0, -7, -8}}), MeshFormat::kPly).message(),
      "face 0 uses vertex 5 of 3");
  std::string unsigned_indices = little_endian_ply(vertices, {{0, 1, 2}, {0, -1, 2}});
  unsigned_indices.replace(unsigned_indices.find("uchar int"), 9, "uchar uint");
  EXPECT_EQ(read_error(unsigned_indices, MeshFormat::kPly).message(),
            "face 1 uses vertex 4294967295 of 3");
  const std::string ascii =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n";
  EXPECT_EQ(read_error(ascii + "3 0 1 2\n3 0 -2147483648 -5\n", MeshFormat::kPly).message(),
            "face 1 uses vertex -2147483648 of 3");
  // A list longer than the bytes left.
  std::string long_list = little_endian_ply(vertices, {{0, 1, 2}, {0, 1, 2}});
  long_list[long_list.size() - 13] = static_cast<char>(200);
  EXPECT_EQ(read_error(long_list, MeshFormat::kPly).message(),
            "invalid ply file: element face item 1: bad list length");
  // Bytes after the last face are not read.
  Mesh mesh =
      read_ok(little_endian_ply(vertices, {{0, 1, 2}, {2, 1, 0}}) + "trailing", MeshFormat::kPly);
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2, 2, 1, 0}));
}

const std::string kOff =
    "OFF\n"
    "5 3 0\n"
    "0 0 0\n"
    "1 0 0\n"
    "1 1 0\n"
    "0 1 0\n"
    "0.1 1e-30 -3.4028235e38\n"
    "4 0 1 2 3\n"
    "3 4 0 2\n"
    "3 4 4 1\n";

TEST(OffReader, ReadsOff) {
  ReadReport report;
  Mesh mesh = read_ok(kOff, MeshFormat::kOff, &report);
  EXPECT_TRUE(same_positions({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.1f, 1e-30f, -3.4028235e38f},
                             mesh.positions));
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 4, 0, 2, 4, 4, 1}));
  EXPECT_EQ(report.polygons_triangulated, 1u);
}

TEST(OffReader, ReadsOffVariants) {
  const std::vector<uint32_t> triangle = {0, 1, 2};
  // Comments, blank lines, CRLF, counts on the header line, no edge count, no final newline.
  Mesh mesh = read_ok(
      "# made by hand\r\n\r\nOFF 3 1\r\n# vertices\r\n0 0 0\r\n1 0 0 # x\r\n0 1 0\r\n3 0 1 2",
      MeshFormat::kOff);
  EXPECT_TRUE(same_positions({0, 0, 0, 1, 0, 0, 0, 1, 0}, mesh.positions));
  EXPECT_EQ(mesh.triangles, triangle);
  // Per-vertex normals and colours (kept: test_attribute_io.cpp).
  mesh = read_ok("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n", MeshFormat::kOff);
  EXPECT_TRUE(same_positions({0, 0, 0, 1, 0, 0, 0, 1, 0}, mesh.positions));
  EXPECT_EQ(mesh.triangles, triangle);
  mesh = read_ok("COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2\n",
                 MeshFormat::kOff);
  EXPECT_TRUE(same_positions({0, 0, 0, 1, 0, 0, 0, 1, 0}, mesh.positions));
  EXPECT_EQ(mesh.triangles, triangle);
  mesh = read_ok(
      "STCNOFF\n3 1 0\n0 0 0 0 0 1 9 9 9 0.5 0.5\n1 0 0 0 0 1 9 9 9 1 0\n0 1 0 0 0 1 9 9 9 0 1\n3 "
      "0 1 2\n",
      MeshFormat::kOff);
  EXPECT_TRUE(same_positions({0, 0, 0, 1, 0, 0, 0, 1, 0}, mesh.positions));
  EXPECT_EQ(mesh.triangles, triangle);
  // Per-face colours (integer or float, 3 or 4 values) end face lines.
  mesh = read_ok(
      "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2 255 0 0\n3 1 3 2 0.5 0.5 0.5 1\n3 0 0 1 3\n",
      MeshFormat::kOff);
  EXPECT_EQ(mesh.triangles, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2, 0, 0, 1}));
  // A point set.
  mesh = read_ok("OFF\n2 0 0\n1 2 3\n4 5 6", MeshFormat::kOff);
  EXPECT_TRUE(same_positions({1, 2, 3, 4, 5, 6}, mesh.positions));
  EXPECT_TRUE(mesh.triangles.empty());
}

TEST(OffReader, OffErrors) {
  struct Case {
    std::string text;
    ErrorCode code;
  };
  const std::vector<Case> cases = {
      {"", ErrorCode::kEmptyMesh},
      {"# nothing\n", ErrorCode::kEmptyMesh},
      {"OFF\n0 0 0\n", ErrorCode::kEmptyMesh},
      {"PLY\n3 1 0\n", ErrorCode::kParseError},
      {"OFF\n", ErrorCode::kParseError},
      {"OFF\nthree 1 0\n", ErrorCode::kParseError},
      {"OFF\n-3 1 0\n0 0 0\n", ErrorCode::kParseError},
      {"4OFF\n3 1 0\n0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 2\n", ErrorCode::kUnsupportedFormat},
      {"OFF BINARY\n", ErrorCode::kUnsupportedFormat},
      // Counts far beyond the file (assimp's OutOfMemory.off).
      {"OFF\n353535235358 6 0\n-0.5 -0.5 0.5\n", ErrorCode::kParseError},
      {"OFF\n3 4000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", ErrorCode::kParseError},
      // Truncated: vertices, then faces.
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n", ErrorCode::kParseError},
      {"OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", ErrorCode::kParseError},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n", ErrorCode::kParseError},
      // A face of 0 corners (assimp's invalid.off), a huge corner count, a bad index.
      {"OFF\n3 4\n0.1 0.2 0.3\n0.2 0.3 0.4\n0.3 0.4 0.5\n0\n220\n4\n", ErrorCode::kParseError},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n", ErrorCode::kParseError},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", ErrorCode::kParseError},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n", ErrorCode::kParseError},
      // Non-numeric and non-finite values.
      {"OFF\n3 1 0\n0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n", ErrorCode::kParseError},
      {"OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", ErrorCode::kParseError},
      // Binary junk after a valid-looking header.
      {"OFF\n3 1 "
       "0\n\x01\x02\x03\x04\x05\x06\x07\x08\x09\x0a\x0b\x0c\x0d\x0e\x0f\x10\x11\x12\x13\x14\n"
       "\x15\x16\x17\x18\x19\n",
       ErrorCode::kParseError},
      {"\x7f"
       "ELF\x02\x01\x01\0\0\0\0\0\0\0\0\0\x03\0\x3e\0"s,
       ErrorCode::kParseError},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    Status status = read_error(c.text, MeshFormat::kOff);
    EXPECT_EQ(status.code(), c.code) << status.message();
  }
  Status status = read_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", MeshFormat::kOff);
  EXPECT_EQ(status.message(), "line 6: face index 7 out of range (3 vertices)");
  status = read_error("OFF\n353535235358 6 0\n-0.5 -0.5 0.5\n", MeshFormat::kOff);
  EXPECT_EQ(status.message(), "line 2: vertex count 353535235358 is more than the file holds");
  status = read_error("OFF\n3 4000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", MeshFormat::kOff);
  EXPECT_EQ(status.message(), "line 6: file ends after 1 of 4000000000 faces");
  status = read_error("OFF\n# comment\n3 2 0\n0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n3 0 1 2\n",
                      MeshFormat::kOff);
  EXPECT_EQ(status.message(), "line 6: non-finite coordinate");
  status = read_error("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n2 0 1\n", MeshFormat::kOff);
  EXPECT_EQ(status.message(), "line 7: face with fewer than 3 corners");
  status = read_error("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n\n# 3 0 1 2\n3 0 1\n",
                      MeshFormat::kOff);
  EXPECT_EQ(status.message(), "line 9: malformed face");
  status = read_error("OFF\n2 0 0\n0 0 0\n1 0\n", MeshFormat::kOff);
  EXPECT_EQ(status.message(), "line 4: malformed vertex");
}

// The reason OFF is not read through OpenMesh: its stream reader parses by the variant
// that the last file-based OpenMesh read of an OFF file detected, process-wide.
TEST(OffReader, OffIsIndependentOfOpenMeshFileReads) {
  test::TempDir dir;
  test::write_file(dir.file("normals.off"),
                   "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n");
  using TriMesh = OpenMesh::TriMesh_ArrayKernelT<>;
  TriMesh other;
  other.request_vertex_normals();
  OpenMesh::IO::Options options = OpenMesh::IO::Options::VertexNormal;
  omerr().disable();
  ASSERT_TRUE(OpenMesh::IO::read_mesh(other, dir.file("normals.off"), options));
  Mesh mesh = read_ok(kOff, MeshFormat::kOff);
  EXPECT_EQ(mesh.vertex_count(), 5u);
  EXPECT_EQ(mesh.face_count(), 4u);
}

TEST(OffReader, RejectsEveryTruncationOfOff) {
  const std::size_t body = kOff.find("5 3 0\n") + 6;
  for (std::size_t length = body; length + 1 < kOff.size(); ++length) {
    const std::string prefix = kOff.substr(0, length);
    SCOPED_TRACE(prefix);
    Mesh mesh;
    Status status = read_mesh_from_memory(prefix, MeshFormat::kOff, mesh);
    EXPECT_FALSE(status.is_ok()) << "read " << mesh.vertex_count() << " vertices, "
                                 << mesh.face_count() << " faces";
  }
}

TEST(OffReader, ReadsArmadilloOff) {
  PM_SKIP_IF_NO_SHARED();
  Mesh mesh;
  Status status = read_mesh(test::shared_mesh_path("armadillo.off"), mesh);
  ASSERT_TRUE(status.is_ok()) << status.message();
  EXPECT_EQ(mesh.vertex_count(), 26002u);
  EXPECT_EQ(mesh.face_count(), 52000u);
}

const std::string kAsciiStl =
    "solid test\n"
    "  facet normal 0 0 1\n"
    "    outer loop\n"
    "      vertex 0 0 0\n"
    "      vertex 1 0 0\n"
    "      vertex 0 1 0\n"
    "    endloop\n"
    "  endfacet\n"
    "  facet normal 0 0 1\n"
    "    outer loop\n"
    "      vertex 1 0 0\n"
    "      vertex 1 1 0\n"
    "      vertex 0 1 0\n"
    "    endloop\n"
    "  endfacet\n"
    "endsolid test\n";

TEST(OpenMeshReaders, ReadsAsciiStlMergingEqualPositions) {
  Mesh mesh = read_ok(kAsciiStl, MeshFormat::kStl);
  EXPECT_EQ(mesh.vertex_count(), 4u);
  EXPECT_EQ(mesh.face_count(), 2u);
  Mesh expected;
  expected.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  expected.triangles = {0, 1, 2, 1, 3, 2};
  EXPECT_TRUE(test::same_faces(expected, mesh));
}

TEST(OpenMeshReaders, StlErrors) {
  EXPECT_EQ(read_error("", MeshFormat::kStl).code(), ErrorCode::kEmptyMesh);
  EXPECT_EQ(read_error("hello, not an stl file", MeshFormat::kStl).code(), ErrorCode::kParseError);
  // A binary STL whose triangle count does not match its size is neither binary nor ASCII.
  std::string binary(84, '\0');
  binary[80] = 5;
  EXPECT_EQ(read_error(binary + std::string(49, '\0'), MeshFormat::kStl).code(),
            ErrorCode::kParseError);
  // No triangles.
  EXPECT_EQ(read_error(std::string(84, '\0'), MeshFormat::kStl).code(), ErrorCode::kEmptyMesh);
  EXPECT_EQ(read_error("solid empty\nendsolid empty\n", MeshFormat::kStl).code(),
            ErrorCode::kEmptyMesh);

  // ASCII STL is checked line by line before OpenMesh, which would turn these into wrong
  // coordinates or silently drop the facet.
  const std::string facet_start = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n";
  const std::string facet_end = "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
  struct Case {
    std::string text;
    std::string message;
  };
  const std::vector<Case> cases = {
      {facet_start + "vertex 1,5 0 0\n" + facet_end, "line 5: malformed vertex"},
      {facet_start + "vertex 1 x 0\n" + facet_end, "line 5: malformed vertex"},
      {facet_start + "vertex nan 0 0\n" + facet_end, "line 5: malformed vertex"},
      {facet_start + "vertex 1 0\n" + facet_end, "line 5: malformed vertex"},
      {facet_start + "vertex 1 0 0 0\n" + facet_end, "line 5: malformed vertex"},
      {facet_start + facet_end, "line 6: expected vertex x y z"},
      {facet_start + "vertex 1 0 0\n" + "vertex 0 1 0\nendloop\n",
       "line 7: file ends inside a solid"},
      {"solid t\nfacet normal 0 0\n", "line 2: expected facet normal x y z, or endsolid"},
      {"solid t\nfacet normal 0 0 1\nouter\n", "line 3: expected outer loop"},
      {"solid t\n\0\0\0\0"s, "line 2: expected facet normal x y z, or endsolid"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    Status status = read_error(c.text, MeshFormat::kStl);
    EXPECT_EQ(status.code(), ErrorCode::kParseError);
    EXPECT_EQ(status.message(), c.message);
  }
}

// ---------------------------------------------------------------------------------------
// Writers and round trips
// ---------------------------------------------------------------------------------------

// Awkward float32 values: not exactly decimal, tiny, the most negative, many digits,
// negative zero, a subnormal, the extremes.
Mesh awkward_mesh() {
  Mesh mesh;
  mesh.positions = {0.1f,        1e-30f,   -3.4028235e38f,  //
                    123456.789f, -0.0f,    1e-45f,          //
                    FLT_MAX,     -FLT_MIN, 1.0f / 3.0f,     //
                    -2.5f,       0.3f,     16777217.0f,     //
                    7.0f,        -1e-7f,   0.0f};
  mesh.triangles = {0, 1, 2, 2, 1, 3, 3, 4, 0, 4, 4, 1};  // the last face is degenerate
  return mesh;
}

TEST(MeshWriter, WritesObjExactly) {
  Mesh mesh;
  mesh.positions = {0.1f, 1e-30f, -3.4028235e38f, 123456.789f, -0.0f, 1.0f, 2.0f, 0.5f, 100.0f};
  mesh.triangles = {0, 1, 2, 2, 1, 0};
  std::string text;
  ASSERT_TRUE(write_mesh_to_memory(mesh, MeshFormat::kObj, text).is_ok());
  EXPECT_EQ(text,
            "v 0.1 1e-30 -3.4028235e+38\n"
            "v 123456.79 -0 1\n"
            "v 2 0.5 100\n"
            "f 1 2 3\n"
            "f 3 2 1\n");
}

// The OBJ and OFF text is allocated at an estimate (12 characters a number); numbers of
// the longest form (15 characters) overrun it, and the buffer must grow without losing a
// byte.
TEST(MeshWriter, WritesTextLongerThanItsEstimate) {
  Mesh mesh;
  std::string expected;
  const int vertices = 3000;
  for (int v = 0; v < vertices; ++v) {
    mesh.positions.insert(mesh.positions.end(), {-FLT_MIN, 1.17549435e-37f, -3.40282347e+38f});
    expected += "v -1.1754944e-38 1.1754944e-37 -3.4028235e+38\n";
  }
  for (int f = 0; f + 2 < vertices; ++f) {
    mesh.triangles.insert(mesh.triangles.end(), {uint32_t(f), uint32_t(f + 1), uint32_t(f + 2)});
    expected += "f " + std::to_string(f + 1) + " " + std::to_string(f + 2) + " " +
                std::to_string(f + 3) + "\n";
  }
  std::string text;
  ASSERT_TRUE(write_mesh_to_memory(mesh, MeshFormat::kObj, text).is_ok());
  EXPECT_EQ(text, expected);

  // OFF's estimate is made the same way.
  expected = "OFF\n3000 2998 0\n";
  for (int v = 0; v < vertices; ++v) expected += "-1.1754944e-38 1.1754944e-37 -3.4028235e+38\n";
  for (int f = 0; f + 2 < vertices; ++f) {
    expected +=
        "3 " + std::to_string(f) + " " + std::to_string(f + 1) + " " + std::to_string(f + 2) + "\n";
  }
  ASSERT_TRUE(write_mesh_to_memory(mesh, MeshFormat::kOff, text).is_ok());
  EXPECT_EQ(text, expected);
}

TEST(MeshWriter, WritesOffExactly) {
  Mesh mesh;
  mesh.positions = {0.1f, 1e-30f, -3.4028235e38f, 1.0f, 2.0f, 3.0f, 0.0f, 0.0f, 0.25f};
  mesh.triangles = {0, 1, 2};
  std::string text;
  ASSERT_TRUE(write_mesh_to_memory(mesh, MeshFormat::kOff, text).is_ok());
  EXPECT_EQ(text,
            "OFF\n3 1 0\n"
            "0.1 1e-30 -3.4028235e+38\n"
            "1 2 3\n"
            "0 0 0.25\n"
            "3 0 1 2\n");
}

TEST(MeshWriter, WritesBinaryPlyLayout) {
  Mesh mesh;
  mesh.positions = {0.1f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f, 8.0f};
  mesh.triangles = {0, 1, 2};
  std::string bytes;
  ASSERT_TRUE(write_mesh_to_memory(mesh, MeshFormat::kPly, bytes).is_ok());
  const std::string header =
      "ply\n"
      "format binary_little_endian 1.0\n"
      "element vertex 3\n"
      "property float x\n"
      "property float y\n"
      "property float z\n"
      "element face 1\n"
      "property list uchar int vertex_indices\n"
      "end_header\n";
  ASSERT_EQ(bytes.substr(0, header.size()), header);
  ASSERT_EQ(bytes.size(), header.size() + 9 * 4 + 13);
  // 0.1f is 0x3dcccccd, little-endian.
  EXPECT_EQ(bytes.substr(header.size(), 4), "\xcd\xcc\xcc\x3d");
  EXPECT_EQ(bytes.substr(header.size() + 36), "\x03\0\0\0\0\x01\0\0\0\x02\0\0\0"s);
}

TEST(MeshWriter, WritesBinaryStlLayout) {
  Mesh mesh;
  mesh.positions = {0, 0, 0, 2, 0, 0, 0, 2, 0};
  mesh.triangles = {0, 1, 2, 0, 0, 1};
  std::string bytes;
  ASSERT_TRUE(write_mesh_to_memory(mesh, MeshFormat::kStl, bytes).is_ok());
  ASSERT_EQ(bytes.size(), 84u + 2 * 50);
  EXPECT_NE(bytes.substr(0, 5), "solid");
  EXPECT_EQ(bytes.substr(80, 4), "\x02\0\0\0"s);
  auto float_at = [&bytes](std::size_t offset) {
    float value;
    std::memcpy(&value, bytes.data() + offset, 4);  // the test host is little-endian
    return value;
  };
  // First facet: normal +z, then the corners.
  EXPECT_EQ(float_at(84), 0.0f);
  EXPECT_EQ(float_at(88), 0.0f);
  EXPECT_EQ(float_at(92), 1.0f);
  EXPECT_EQ(float_at(96 + 12), 2.0f);
  EXPECT_EQ(bytes.substr(84 + 48, 2), "\0\0"s);
  // Degenerate facet: zero normal.
  EXPECT_EQ(float_at(134), 0.0f);
  EXPECT_EQ(float_at(138), 0.0f);
  EXPECT_EQ(float_at(142), 0.0f);
}

TEST(MeshWriter, RoundTripsIndexedFormatsBitExactly) {
  const Mesh mesh = awkward_mesh();
  for (MeshFormat format : {MeshFormat::kObj, MeshFormat::kPly, MeshFormat::kOff}) {
    SCOPED_TRACE(mesh_format_name(format));
    std::string bytes;
    ASSERT_TRUE(write_mesh_to_memory(mesh, format, bytes).is_ok());
    ReadReport report;
    Mesh back = read_ok(bytes, format, &report);
    EXPECT_TRUE(same_positions(mesh.positions, back.positions));
    EXPECT_EQ(mesh.triangles, back.triangles);
    EXPECT_EQ(report.polygons_triangulated, 0u);
    EXPECT_EQ(report.ignored_lines, 0u);
  }
}

TEST(MeshWriter, RoundTripsStlFacesBitExactly) {
  // STL keeps no indices: the reader merges equal positions and drops faces that became
  // degenerate, so compare faces by their corner positions, without the degenerate one.
  Mesh mesh = awkward_mesh();
  mesh.triangles.resize(mesh.triangles.size() - 3);
  std::string bytes;
  ASSERT_TRUE(write_mesh_to_memory(mesh, MeshFormat::kStl, bytes).is_ok());
  Mesh back = read_ok(bytes, MeshFormat::kStl);
  EXPECT_TRUE(test::same_faces(mesh, back));
}

TEST(MeshWriter, RoundTripsSharedMeshes) {
  PM_SKIP_IF_NO_SHARED();
  for (const char* name : {"cow.obj", "armadillo.off"}) {
    SCOPED_TRACE(name);
    Mesh mesh;
    ASSERT_TRUE(read_mesh(test::shared_mesh_path(name), mesh).is_ok());
    for (MeshFormat format :
         {MeshFormat::kObj, MeshFormat::kPly, MeshFormat::kOff, MeshFormat::kStl}) {
      SCOPED_TRACE(mesh_format_name(format));
      std::string bytes;
      ASSERT_TRUE(write_mesh_to_memory(mesh, format, bytes).is_ok());
      Mesh back = read_ok(bytes, format);
      if (format == MeshFormat::kStl) {
        EXPECT_TRUE(test::same_faces(mesh, back));
      } else {
        EXPECT_TRUE(same_positions(mesh.positions, back.positions));
        EXPECT_EQ(mesh.triangles, back.triangles);
      }
    }
  }
}

TEST(MeshWriter, WritesEmptyMesh) {
  const Mesh empty;
  for (MeshFormat format :
       {MeshFormat::kObj, MeshFormat::kPly, MeshFormat::kOff, MeshFormat::kStl}) {
    std::string bytes = "old contents";
    EXPECT_TRUE(write_mesh_to_memory(empty, format, bytes).is_ok());
    EXPECT_NE(bytes, "old contents");
  }
}

TEST(MeshWriter, RejectsInvalidMeshes) {
  std::string bytes;
  Mesh bad_index;
  bad_index.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  bad_index.triangles = {0, 1, 3};
  Status status = write_mesh_to_memory(bad_index, MeshFormat::kObj, bytes);
  EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(status.message(), "face 0 uses vertex 3 of 3");

  Mesh not_finite;
  not_finite.positions = {0, 0, 0, 1, std::nanf(""), 0};
  EXPECT_EQ(write_mesh_to_memory(not_finite, MeshFormat::kPly, bytes).code(),
            ErrorCode::kInvalidArgument);

  Mesh ragged;
  ragged.positions = {0, 0};
  EXPECT_EQ(write_mesh_to_memory(ragged, MeshFormat::kOff, bytes).code(),
            ErrorCode::kInvalidArgument);

  EXPECT_EQ(write_mesh_to_memory(Mesh(), MeshFormat::kUnknown, bytes).code(),
            ErrorCode::kUnsupportedFormat);
}

// write_mesh_to_sink(): the bytes of write_mesh_to_memory(), in pieces of a megabyte or so.
namespace {

struct Pieces {
  std::string whole;
  std::vector<std::size_t> sizes;
  MeshByteSink sink() {
    return [this](std::string_view piece) {
      sizes.push_back(piece.size());
      whole.append(piece);
      return Status::ok();
    };
  }
};

const MeshFormat kEveryFormat[] = {MeshFormat::kObj, MeshFormat::kPly,  MeshFormat::kOff,
                                   MeshFormat::kStl, MeshFormat::kGltf, MeshFormat::kGlb};

// The pieces write_mesh_to_sink() gives, checked against write_mesh_to_memory()'s bytes; the
// latter's size in *size.
Pieces pieces_of(const Mesh& mesh, MeshFormat format, std::size_t* size) {
  std::string expected;
  EXPECT_TRUE(write_mesh_to_memory(mesh, format, expected).is_ok());
  Pieces pieces;
  EXPECT_TRUE(write_mesh_to_sink(mesh, format, pieces.sink()).is_ok());
  // Not EXPECT_EQ: gtest's diff of two megabytes of text would take gigabytes.
  EXPECT_TRUE(pieces.whole == expected)
      << pieces.whole.size() << " bytes given, " << expected.size() << " written to memory";
  *size = expected.size();
  return pieces;
}

}  // namespace

TEST(MeshWriterSink, GivesTheBytesOfMemoryInPieces) {
  // 160 x 160: every attribute, and each format's text or binary above a megabyte (OBJ
  // about 2.4 MB, STL 2.5 MB), so that each is given in several pieces.
  const Mesh mesh = test::seamed_grid(160);
  for (MeshFormat format : kEveryFormat) {
    SCOPED_TRACE(mesh_format_name(format));
    std::size_t size = 0;
    const Pieces pieces = pieces_of(mesh, format, &size);
    // A megabyte each but the last, or short of it by less than a line (text) or an element.
    const std::size_t megabytes = (size + (std::size_t{1} << 20) - 1) >> 20;
    EXPECT_GE(megabytes, 2u);
    EXPECT_GE(pieces.sizes.size(), megabytes);
    EXPECT_LE(pieces.sizes.size(), megabytes + 1);
    for (std::size_t size : pieces.sizes) {
      EXPECT_GT(size, 0u);
      EXPECT_LE(size, std::size_t{1} << 20);
    }
  }
}

TEST(MeshWriterSink, GivesSmallMeshesInOnePieceAndEmptyOnesInNone) {
  const Mesh mesh = test::seamed_grid(4);
  for (MeshFormat format : kEveryFormat) {
    SCOPED_TRACE(mesh_format_name(format));
    std::size_t size = 0;
    EXPECT_EQ(pieces_of(mesh, format, &size).sizes.size(), 1u);
  }
  Pieces empty;
  ASSERT_TRUE(write_mesh_to_sink(Mesh(), MeshFormat::kObj, empty.sink()).is_ok());
  EXPECT_TRUE(empty.sizes.empty()) << "an empty OBJ is no bytes: no piece, none empty";
}

TEST(MeshWriterSink, StopsAtTheSinksFailureAndReturnsIt) {
  const Mesh mesh = test::seamed_grid(160);
  for (MeshFormat format : kEveryFormat) {
    SCOPED_TRACE(mesh_format_name(format));
    int calls = 0;
    const Status status = write_mesh_to_sink(mesh, format, [&](std::string_view) {
      return ++calls == 2 ? Status(ErrorCode::kIoError, "disk full") : Status::ok();
    });
    EXPECT_EQ(status.code(), ErrorCode::kIoError);
    EXPECT_EQ(status.message(), "disk full");
    EXPECT_EQ(calls, 2) << "no piece after the failure";
  }
}

TEST(MeshWriterSink, RefusesABadMeshBeforeAnyPiece) {
  Mesh bad_index;
  bad_index.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  bad_index.triangles = {0, 1, 3};
  Mesh bad_name = test::seamed_grid(4);
  bad_name.material_names[0] = "line\nbreak";  // would not read back as itself
  for (MeshFormat format : kEveryFormat) {
    SCOPED_TRACE(mesh_format_name(format));
    int calls = 0;
    const MeshByteSink counting = [&](std::string_view) {
      ++calls;
      return Status::ok();
    };
    const Status status = write_mesh_to_sink(bad_index, format, counting);
    EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument);
    EXPECT_EQ(status.message(), "face 0 uses vertex 3 of 3");
    if (format == MeshFormat::kObj || format == MeshFormat::kPly) {
      std::string bytes;
      const Status memory = write_mesh_to_memory(bad_name, format, bytes);
      ASSERT_FALSE(memory.is_ok());
      const Status sunk = write_mesh_to_sink(bad_name, format, counting);
      EXPECT_EQ(sunk.code(), memory.code());
      EXPECT_EQ(sunk.message(), memory.message());
    }
    EXPECT_EQ(calls, 0);
  }
  EXPECT_EQ(write_mesh_to_sink(Mesh(), MeshFormat::kUnknown, [](std::string_view) {
              return Status::ok();
            }).code(),
            ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(write_mesh_to_sink(Mesh(), MeshFormat::kObj, MeshByteSink()).code(),
            ErrorCode::kInvalidArgument);
}

TEST(MeshWriterSink, ASinksExceptionIsAStatus) {
  const Mesh mesh = test::seamed_grid(4);
  const Status thrown = write_mesh_to_sink(mesh, MeshFormat::kObj, [](std::string_view) -> Status {
    throw std::runtime_error("the caller's bug");
  });
  EXPECT_EQ(thrown.code(), ErrorCode::kInternal);
  const Status no_memory =
      write_mesh_to_sink(mesh, MeshFormat::kPly, [](std::string_view) -> Status {
        throw std::bad_alloc();
      });
  EXPECT_EQ(no_memory.code(), ErrorCode::kResourceLimit);
}

// ---------------------------------------------------------------------------------------
// Formats, files
// ---------------------------------------------------------------------------------------

TEST(MeshFormat, FromPath) {
  EXPECT_EQ(mesh_format_from_path("mesh.obj"), MeshFormat::kObj);
  EXPECT_EQ(mesh_format_from_path("MESH.OBJ"), MeshFormat::kObj);
  EXPECT_EQ(mesh_format_from_path(".obj"), MeshFormat::kObj);
  EXPECT_EQ(mesh_format_from_path(".Ply"), MeshFormat::kPly);
  EXPECT_EQ(mesh_format_from_path("/data/scan.v2.ply"), MeshFormat::kPly);
  EXPECT_EQ(mesh_format_from_path("dir.stl/model.Off"), MeshFormat::kOff);
  EXPECT_EQ(mesh_format_from_path("C:\\models\\part.STL"), MeshFormat::kStl);
  EXPECT_EQ(mesh_format_from_path(""), MeshFormat::kUnknown);
  EXPECT_EQ(mesh_format_from_path("-"), MeshFormat::kUnknown);
  EXPECT_EQ(mesh_format_from_path("obj"), MeshFormat::kUnknown);
  EXPECT_EQ(mesh_format_from_path("mesh."), MeshFormat::kUnknown);
  EXPECT_EQ(mesh_format_from_path("mesh.obj.gz"), MeshFormat::kUnknown);
  EXPECT_EQ(mesh_format_from_path("dir.obj/mesh"), MeshFormat::kUnknown);
  EXPECT_EQ(mesh_format_from_path("mesh.objx"), MeshFormat::kUnknown);
  EXPECT_EQ(mesh_format_from_path("mesh.pm"), MeshFormat::kUnknown);
}

TEST(MeshFormat, Names) {
  EXPECT_STREQ(mesh_format_name(MeshFormat::kObj), "obj");
  EXPECT_STREQ(mesh_format_name(MeshFormat::kPly), "ply");
  EXPECT_STREQ(mesh_format_name(MeshFormat::kOff), "off");
  EXPECT_STREQ(mesh_format_name(MeshFormat::kStl), "stl");
  EXPECT_STREQ(mesh_format_name(MeshFormat::kUnknown), "unknown");
  for (MeshFormat format :
       {MeshFormat::kObj, MeshFormat::kPly, MeshFormat::kOff, MeshFormat::kStl}) {
    EXPECT_EQ(mesh_format_from_path(std::string(".") + mesh_format_name(format)), format);
  }
}

TEST(ReadMesh, ReadsFilesOfEachFormat) {
  test::TempDir dir;
  test::write_file(dir.file("a.obj"), kTriangleObj);
  test::write_file(dir.file("b.PLY"), kAsciiPly);
  test::write_file(dir.file("c.off"), kOff);
  test::write_file(dir.file("d.stl"), kAsciiStl);
  const std::pair<const char*, std::size_t> expected_faces[] = {
      {"a.obj", 1}, {"b.PLY", 3}, {"c.off", 4}, {"d.stl", 2}};
  for (const auto& [name, faces] : expected_faces) {
    SCOPED_TRACE(name);
    Mesh mesh;
    ReadReport report;
    Status status = read_mesh(dir.file(name), mesh, &report);
    ASSERT_TRUE(status.is_ok()) << status.message();
    EXPECT_EQ(mesh.face_count(), faces);
  }
}

TEST(ReadMesh, Errors) {
  test::TempDir dir;
  Mesh mesh;
  Status status = read_mesh(dir.file("missing.obj"), mesh);
  EXPECT_EQ(status.code(), ErrorCode::kIoError);
  EXPECT_EQ(status.message(), "cannot open file (no such file or directory)");

  std::filesystem::create_directory(dir.file("folder.obj"));
  status = read_mesh(dir.file("folder.obj"), mesh);
  EXPECT_EQ(status.code(), ErrorCode::kIoError);
  EXPECT_FALSE(status.message().empty());

  test::write_file(dir.file("mesh.txt"), kTriangleObj);
  EXPECT_EQ(read_mesh(dir.file("mesh.txt"), mesh).code(), ErrorCode::kUnsupportedFormat);
  EXPECT_EQ(read_mesh_from_memory(kTriangleObj, MeshFormat::kUnknown, mesh).code(),
            ErrorCode::kUnsupportedFormat);

  test::write_file(dir.file("empty.obj"), "");
  EXPECT_EQ(read_mesh(dir.file("empty.obj"), mesh).code(), ErrorCode::kEmptyMesh);
}

// OpenMesh's readers are process-wide singletons; reads from several threads must not mix.
TEST(ReadMesh, ConcurrentOpenMeshReads) {
  std::string ply;
  ASSERT_TRUE(write_mesh_to_memory(awkward_mesh(), MeshFormat::kPly, ply).is_ok());
  std::vector<std::thread> threads;
  std::vector<int> failures(4, 0);
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < 50; ++i) {
        Mesh mesh;
        const bool ok = (t % 2 ? read_mesh_from_memory(ply, MeshFormat::kPly, mesh)
                               : read_mesh_from_memory(kOff, MeshFormat::kOff, mesh))
                            .is_ok();
        failures[t] += !ok || mesh.face_count() != 4u;
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(failures, std::vector<int>(4, 0));
}

// ---------------------------------------------------------------------------------------
// Robustness: damaged and foreign files must give an error (or a mesh), never a crash
// ---------------------------------------------------------------------------------------

TEST(Robustness, SurvivesRandomDamage) {
  const Mesh mesh = awkward_mesh();
  std::mt19937 random(12345);
  for (MeshFormat format :
       {MeshFormat::kObj, MeshFormat::kPly, MeshFormat::kOff, MeshFormat::kStl}) {
    SCOPED_TRACE(mesh_format_name(format));
    std::string original;
    ASSERT_TRUE(write_mesh_to_memory(mesh, format, original).is_ok());
    for (int trial = 0; trial < 300; ++trial) {
      std::string damaged = original;
      const int edits = 1 + static_cast<int>(random() % 4);
      for (int e = 0; e < edits; ++e) {
        const std::size_t at = random() % damaged.size();
        switch (random() % 3) {
          case 0:
            damaged[at] = static_cast<char>(random());
            break;
          case 1:
            damaged.erase(at, 1 + random() % 8);
            break;
          default:
            damaged.insert(at, 1, "0123456789 -.\n#e9"[random() % 17]);
            break;
        }
        if (damaged.empty()) damaged = "x";
      }
      Mesh result;
      Status status = read_mesh_from_memory(damaged, format, result);
      if (!status.is_ok()) {
        EXPECT_FALSE(status.message().empty());
      } else {
        for (uint32_t index : result.triangles) ASSERT_LT(index, result.vertex_count());
        for (float coordinate : result.positions) ASSERT_TRUE(std::isfinite(coordinate));
      }
    }
  }
}

TEST(Robustness, ReadsAssimpTestModelsWithoutCrashing) {
  const std::filesystem::path root = "/usr/share/assimp/models";
  if (!std::filesystem::is_directory(root)) {
    GTEST_SKIP() << root << " not found (Debian package assimp-testmodels)";
  }
  int files = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file()) continue;
    const std::string path = entry.path().string();
    if (mesh_format_from_path(path) == MeshFormat::kUnknown) continue;
    SCOPED_TRACE(path);
    ++files;
    Mesh mesh;
    Status status = read_mesh(path, mesh);
    if (status.is_ok()) {
      for (uint32_t index : mesh.triangles) ASSERT_LT(index, mesh.vertex_count());
    } else {
      EXPECT_FALSE(status.message().empty());
    }
  }
  EXPECT_GT(files, 0);
}

}  // namespace
}  // namespace pm
