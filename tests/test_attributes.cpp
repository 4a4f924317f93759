// Attributes through the encoder and the levels of detail (Hoppe 1996, §3 wedges): every
// face's corner attributes come back bit for bit at full detail; at coarser levels the
// seams and material borders stay on the input's, and no texture triangle turns over.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "test_util.h"

namespace pm {
namespace {

uint32_t bits(float x) {
  uint32_t b;
  std::memcpy(&b, &x, 4);
  return b;
}

// The collapse loop (one since issue 25, the former fast loop: the names keep "Fast") with
// either metric, with one heap or in regions on two threads (asked for here; by default on
// meshes of 16384 vertices or more; the rounds run while more than 1,024 vertices and 2,048
// faces are left above the limits, and stop when the cuts hold an eighth of them: on the
// large grid below, not on spot nor on the small grids). Each keeps the attributes the same
// way.
enum class Loop { kFast, kFastRegions, kFastSchroeder, kFastSchroederRegions };

std::string loop_name(Loop loop) {
  switch (loop) {
    case Loop::kFast: return "Fast";
    case Loop::kFastRegions: return "FastRegions";
    case Loop::kFastSchroeder: return "FastSchroeder";
    case Loop::kFastSchroederRegions: return "FastSchroederRegions";
  }
  return "";
}

EncodeOptions options_for(Loop loop) {
  EncodeOptions options;
  const bool regions = loop == Loop::kFastRegions || loop == Loop::kFastSchroederRegions;
  options.metric = loop == Loop::kFastSchroeder || loop == Loop::kFastSchroederRegions
                       ? Metric::kSchroeder
                       : Metric::kQuadric;
  options.fast_partition_vertices = regions ? 1 : 0;
  options.threads = regions ? 2 : 1;
  return options;
}

ProgressiveMesh encode_ok(const Mesh& mesh, Loop loop, bool drop = false) {
  EncodeOptions options = options_for(loop);
  options.drop_attributes = drop;
  ProgressiveMesh pm;
  EncodeStats stats;
  const Status status = encode(mesh, options, pm, &stats);
  EXPECT_TRUE(status.ok()) << status.message();
  EXPECT_TRUE(test::ok(validate(pm)));
  return pm;
}


// The corner values of face f at vertex slot k, for seam tests on the output.
struct EdgeKey {
  uint32_t a, b;
  bool operator<(const EdgeKey& o) const { return std::tie(a, b) < std::tie(o.a, o.b); }
};

// Edges of the output where the two faces differ in the given per-corner table (uvs or
// normals) at either end, or in material (table == nullptr).
std::vector<EdgeKey> seam_edges(const Mesh& m, const std::vector<uint32_t>* ids,
                                const std::vector<float>* values, int dims) {
  std::map<EdgeKey, std::vector<std::pair<std::size_t, int>>> edge_faces;  // face, corner of a
  for (std::size_t f = 0; f < m.face_count(); ++f)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = m.triangles[3 * f + k], b = m.triangles[3 * f + (k + 1) % 3];
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back({f, k});
    }
  auto value_at = [&](std::size_t f, uint32_t vertex) {
    std::vector<uint32_t> out;
    for (int k = 0; k < 3; ++k) {
      if (m.triangles[3 * f + k] != vertex) continue;
      const uint32_t id = (*ids)[3 * f + k];
      for (int d = 0; d < dims; ++d) out.push_back(bits((*values)[dims * id + d]));
    }
    return out;
  };
  std::vector<EdgeKey> seams;
  for (const auto& [edge, faces] : edge_faces) {
    if (faces.size() != 2) continue;
    const std::size_t f = faces[0].first, g = faces[1].first;
    const bool seam = ids ? value_at(f, edge.a) != value_at(g, edge.a) ||
                                value_at(f, edge.b) != value_at(g, edge.b)
                          : m.face_materials[f] != m.face_materials[g];
    if (seam) seams.push_back(edge);
  }
  return seams;
}

class AttributesByLoop : public ::testing::TestWithParam<Loop> {};

// A square bulged into a dome, its texture cut along a gentle arc: the middle row of
// vertices bends within the square (the rows between follow), and the faces below that
// row are one chart, those above another. A collapse along the arc slides the seam within
// the surface, which the distance to the surface does not see; only what the encoder
// charges for the slide (SeamDrift) keeps the arc where the texture has it.
Mesh curved_square_with_arced_seam(int n, double bend, double dome) {
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = double(i) / n, t = double(j) / n;
      const double y = t + bend * std::sin(M_PI * x) * std::sin(M_PI * t);
      m.positions.insert(m.positions.end(), {float(x), float(y), float(dome * std::sin(M_PI * x) * std::sin(M_PI * t))});
    }
  auto id = [n](int i, int j) { return uint32_t(j * (n + 1) + i); };
  // UV entries: chart 0 is the vertex's xy, chart 1 the same moved by (2, 0); an entry per
  // vertex and chart.
  const uint32_t count = uint32_t(m.positions.size() / 3);
  for (int chart = 0; chart < 2; ++chart)
    for (uint32_t v = 0; v < count; ++v)
      m.uvs.insert(m.uvs.end(), {m.positions[3 * v] + 2.0f * chart, m.positions[3 * v + 1]});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t shift = j < n / 2 ? 0 : count;
      for (const std::array<uint32_t, 3>& f :
           {std::array<uint32_t, 3>{id(i, j), id(i + 1, j), id(i + 1, j + 1)},
            std::array<uint32_t, 3>{id(i, j), id(i + 1, j + 1), id(i, j + 1)}}) {
        m.triangles.insert(m.triangles.end(), f.begin(), f.end());
        for (uint32_t v : f) m.uv_indices.push_back(v + shift);
      }
    }
  return m;
}

double distance_to_segment(const float* p, const float* a, const float* b) {
  double ab[3], ap[3], t = 0, len2 = 0;
  for (int d = 0; d < 3; ++d) ab[d] = double(b[d]) - a[d], ap[d] = double(p[d]) - a[d];
  for (int d = 0; d < 3; ++d) t += ap[d] * ab[d], len2 += ab[d] * ab[d];
  t = len2 > 0 ? std::clamp(t / len2, 0.0, 1.0) : 0.0;
  double sum = 0;
  for (int d = 0; d < 3; ++d) sum += (ap[d] - t * ab[d]) * (ap[d] - t * ab[d]);
  return std::sqrt(sum);
}

// The largest distance from a vertex of the input's UV seams to the level's UV seams.
double seam_drift(const Mesh& input, const Mesh& level) {
  const auto input_seams = seam_edges(input, &input.uv_indices, &input.uvs, 2);
  const auto level_seams = seam_edges(level, &level.uv_indices, &level.uvs, 2);
  double worst = 0;
  for (const EdgeKey& e : input_seams)
    for (uint32_t v : {e.a, e.b}) {
      double nearest = INFINITY;
      for (const EdgeKey& s : level_seams)
        nearest = std::min(nearest, distance_to_segment(&input.positions[3 * v],
                                                        &level.positions[3 * s.a],
                                                        &level.positions[3 * s.b]));
      worst = std::max(worst, nearest);
    }
  return worst;
}

TEST_P(AttributesByLoop, ATextureSeamSlidesWithinTheSurfaceLessThanTheSurfaceMoves) {
  const Mesh dome = curved_square_with_arced_seam(24, 0.1, 0.2);
  const ProgressiveMesh pm = encode_ok(dome, GetParam());
  // Each level's seams stay closer to the input's seam than half the level's error bound
  // (the surface's distance from the input). Charged like the surface distance, a seam
  // slid as far as the bound (up to 0.92 of it here); charged 3.5 times, it stays near a
  // quarter.
  std::size_t checked = 0;
  for (std::size_t level = 0; level <= pm.split_count(); ++level) {
    const Mesh lod = extract_level(pm, level);
    if (lod.face_count() < dome.face_count() / 20) continue;
    const double drift = seam_drift(dome, lod), bound = error_at_level(pm, level);
    EXPECT_LE(drift, 0.5 * bound) << lod.face_count() << " faces";
    ++checked;
  }
  EXPECT_GT(checked, 250u);
}

TEST_P(AttributesByLoop, FullDetailGivesEveryFacesCornerAttributesBitForBit) {
  const Mesh grid = test::seamed_grid(24);
  const ProgressiveMesh pm = encode_ok(grid, GetParam());
  const Mesh full = extract_level(pm, pm.split_count());
  EXPECT_TRUE(test::same_attributed_faces(grid, full));
  // The value tables come back whole, in the order the stream meets their entries
  // (order_attribute_tables; the input's under keep_order, tested with the stream).
  const auto sorted_pairs = [](const std::vector<float>& values, std::size_t components) {
    std::vector<std::vector<float>> entries;
    for (std::size_t i = 0; i < values.size(); i += components)
      entries.emplace_back(values.begin() + i, values.begin() + i + components);
    std::sort(entries.begin(), entries.end());
    return entries;
  };
  EXPECT_EQ(sorted_pairs(full.uvs, 2), sorted_pairs(grid.uvs, 2));
  EXPECT_EQ(sorted_pairs(full.normals, 3), sorted_pairs(grid.normals, 3));
  EXPECT_EQ(full.material_names, grid.material_names);
  EXPECT_EQ(full.material_libraries, grid.material_libraries);
}

TEST_P(AttributesByLoop, SeamsAndBordersStayOnTheInputsAtEveryCoarserLevel) {
  const Mesh grid = test::seamed_grid(24);
  const ProgressiveMesh pm = encode_ok(grid, GetParam());
  // The discontinuities pin little: the grid still simplifies far.
  EXPECT_LT(faces_at_level(pm, 0), grid.face_count() / 20);
  for (double ratio : {0.5, 0.1, 0.02, 0.0}) {
    const std::size_t level = level_for_faces(pm, std::size_t(ratio * grid.face_count()));
    const Mesh lod = extract_level(pm, level);
    SCOPED_TRACE("level " + std::to_string(level) + ", " + std::to_string(lod.face_count()) +
                 " faces");
    auto x = [&](uint32_t v) { return lod.positions[3 * v]; };
    auto y = [&](uint32_t v) { return lod.positions[3 * v + 1]; };
    const auto uv_seams = seam_edges(lod, &lod.uv_indices, &lod.uvs, 2);
    const auto crease = seam_edges(lod, &lod.normal_indices, &lod.normals, 3);
    const auto border = seam_edges(lod, nullptr, nullptr, 0);
    EXPECT_FALSE(uv_seams.empty());
    EXPECT_FALSE(crease.empty());
    EXPECT_FALSE(border.empty());
    for (const EdgeKey& e : uv_seams) EXPECT_TRUE(x(e.a) == 0.5f && x(e.b) == 0.5f);
    for (const EdgeKey& e : crease) EXPECT_TRUE(y(e.a) == 0.5f && y(e.b) == 0.5f);
    auto on_diagonal = [&](uint32_t v) { return x(v) == y(v); };
    for (const EdgeKey& e : border) EXPECT_TRUE(on_diagonal(e.a) && on_diagonal(e.b));
  }
}

TEST_P(AttributesByLoop, NoTextureTriangleTurnsOverAtAnyLevel) {
  const Mesh grid = test::seamed_grid(24);
  const ProgressiveMesh pm = encode_ok(grid, GetParam());
  const Mesh full = extract_level(pm, pm.split_count());
  auto uv_area = [](const Mesh& m, std::size_t f) {
    const float* a = &m.uvs[2 * m.uv_indices[3 * f]];
    const float* b = &m.uvs[2 * m.uv_indices[3 * f + 1]];
    const float* c = &m.uvs[2 * m.uv_indices[3 * f + 2]];
    return (double(b[0]) - a[0]) * (double(c[1]) - a[1]) - (double(b[1]) - a[1]) * (double(c[0]) - a[0]);
  };
  for (std::size_t level = 0; level < pm.split_count(); level += 37) {
    const Mesh lod = extract_level(pm, level);
    // Face k of a level is face k of full detail, coarser (faces keep their ids).
    for (std::size_t f = 0; f < lod.face_count(); ++f) {
      const double before = uv_area(full, f), now = uv_area(lod, f);
      ASSERT_TRUE(before == 0 || ((before > 0) == (now > 0) && now != 0))
          << "level " << level << " face " << f << ": texture area " << now << ", input "
          << before;
    }
  }
}

TEST_P(AttributesByLoop, ColoursTravelWithTheirVertices) {
  const Mesh grid = test::seamed_grid(16);
  const ProgressiveMesh pm = encode_ok(grid, GetParam());
  for (std::size_t level : {std::size_t{0}, pm.split_count() / 3, pm.split_count()}) {
    const Mesh lod = extract_level(pm, level);
    ASSERT_EQ(lod.color_components, 3u);
    ASSERT_EQ(lod.colors.size(), 3 * lod.vertex_count());
    for (std::size_t v = 0; v < lod.vertex_count(); ++v) {
      EXPECT_EQ(bits(lod.colors[3 * v]), bits(lod.positions[3 * v]));
      EXPECT_EQ(bits(lod.colors[3 * v + 1]), bits(lod.positions[3 * v + 1]));
    }
  }
}

TEST_P(AttributesByLoop, DropAttributesKeepsGeometryOnly) {
  const Mesh grid = test::seamed_grid(16);
  const ProgressiveMesh pm = encode_ok(grid, GetParam(), /*drop=*/true);
  EXPECT_FALSE(pm.has_uvs() || pm.has_normals() || pm.has_materials());
  EXPECT_EQ(pm.color_components, 0u);
  EXPECT_TRUE(pm.colors.empty() && pm.material_names.empty() && pm.material_libraries.empty());
  const Mesh full = extract_level(pm, pm.split_count());
  EXPECT_FALSE(full.has_attributes());
  EXPECT_TRUE(test::same_faces(grid, full));
  // Without seams to keep, it simplifies at least as far.
  const ProgressiveMesh with = encode_ok(grid, GetParam());
  EXPECT_LE(pm.base_face_count(), with.base_face_count());
}

INSTANTIATE_TEST_SUITE_P(Loops, AttributesByLoop,
                         ::testing::Values(Loop::kFast,
                                           Loop::kFastRegions, Loop::kFastSchroeder,
                                           Loop::kFastSchroederRegions),
                         [](const auto& info) { return loop_name(info.param); });

TEST(Attributes, CornersWithoutAttributesAndFacesWithoutMaterialStayThatWay) {
  Mesh grid = test::seamed_grid(12);
  // Every third face has no texture coordinates, every fifth no material.
  for (std::size_t f = 0; f < grid.face_count(); f += 3)
    for (int k = 0; k < 3; ++k) grid.uv_indices[3 * f + k] = kNoAttribute;
  for (std::size_t f = 0; f < grid.face_count(); f += 5) grid.face_materials[f] = kNoAttribute;
  for (const Loop loop : {Loop::kFast}) {
    const ProgressiveMesh pm = encode_ok(grid, loop);
    EXPECT_TRUE(test::same_attributed_faces(grid, extract_level(pm, pm.split_count())))
        << loop_name(loop);
  }
}

// A strip of 4 x 2 squares, its texture cut at x = 2: the corners left of the cut take
// chart 0 (u = x), those right of it chart 1 (u = x + 10), so the vertices at x = 2 carry
// two texture coordinates. The collapse loop slides the cut's vertices along it only, as the
// default loop does: at every level the seam runs along x = 2, whole (from y = 0 to y = 2)
// while faces of both charts are left, and every face keeps its chart.
TEST(Attributes, TheFastLoopKeepsAUvSeamWholeAtEveryLevel) {
  Mesh m;
  for (int y = 0; y <= 2; ++y)
    for (int x = 0; x <= 4; ++x)
      m.positions.insert(m.positions.end(), {float(x), float(y), 0.05f * float(x * (4 - x) * y * (2 - y))});
  // Chart 0: ids 0-14 (u = x, v = y); chart 1: ids 15-29 (u = x + 10).
  for (int chart = 0; chart < 2; ++chart)
    for (int y = 0; y <= 2; ++y)
      for (int x = 0; x <= 4; ++x) m.uvs.insert(m.uvs.end(), {float(x + 10 * chart), float(y)});
  m.triangles = {0, 1, 6,  0, 6, 5,  1, 2, 7,  1, 7, 6,  2, 3, 8,  2, 8, 7,  3, 4, 9,  3, 9, 8,
                 5, 6, 11, 5, 11, 10, 6, 7, 12, 6, 12, 11, 7, 8, 13, 7, 13, 12, 8, 9, 14, 8, 14, 13};
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    const bool right = (f / 2) % 4 >= 2;
    for (int k = 0; k < 3; ++k) m.uv_indices.push_back(m.triangles[3 * f + k] + (right ? 15 : 0));
  }
  for (const Loop loop : {Loop::kFast, Loop::kFastRegions}) {
    SCOPED_TRACE(loop_name(loop));
    const ProgressiveMesh pm = encode_ok(m, loop);
    EXPECT_GT(pm.split_count(), 4u);
    const Mesh full = extract_level(pm, pm.split_count());
    EXPECT_TRUE(test::same_attributed_faces(m, full));
    std::size_t with_both = 0;
    for (std::size_t level = 0; level <= pm.split_count(); ++level) {
      const Mesh lod = extract_level(pm, level);
      double length = 0;
      for (const EdgeKey& e : seam_edges(lod, &lod.uv_indices, &lod.uvs, 2)) {
        EXPECT_EQ(lod.positions[3 * e.a], 2.0f) << "level " << level;
        EXPECT_EQ(lod.positions[3 * e.b], 2.0f) << "level " << level;
        length += std::abs(lod.positions[3 * e.a + 1] - lod.positions[3 * e.b + 1]);
      }
      // Face k of a level is face k of full detail: its corners' chart is the input's.
      bool charts[2] = {false, false};
      for (std::size_t f = 0; f < lod.face_count(); ++f) {
        const bool right = full.uvs[2 * full.uv_indices[3 * f]] >= 10.0f;
        charts[right] = true;
        for (int k = 0; k < 3; ++k)
          EXPECT_EQ(lod.uvs[2 * lod.uv_indices[3 * f + k]] >= 10.0f, right)
              << "level " << level << " face " << f;
      }
      // Whole while both charts have faces (near the base, one side may be gone: a single
      // triangle is left of the strip).
      if (charts[0] && charts[1]) {
        EXPECT_EQ(length, 2.0) << "level " << level;
        ++with_both;
      }
    }
    EXPECT_GE(with_both, 4u);
  }
}

// In regions, the collapse loop's attribute state is each region's own: the same stream for
// any number of threads.
TEST(Attributes, TheFastLoopInRegionsGivesTheSameStreamForAnyThreadCount) {
  // 80,000 faces: rounds run (on small meshes the cuts between regions hold more than the
  // eighth of the vertices at which they stop, and one heap does it all).
  const Mesh grid = test::seamed_grid(200);
  std::string first;
  for (const unsigned threads : {1u, 2u, 4u}) {
    EncodeOptions options = options_for(Loop::kFastRegions);
    options.threads = threads;
    ProgressiveMesh pm;
    EncodeStats stats;
    ASSERT_TRUE(encode(grid, options, pm, &stats).ok());
    std::string bytes;
    ASSERT_TRUE(write_pm(pm, WriteOptions{}, bytes).ok());
    if (first.empty())
      first = bytes;
    else
      EXPECT_TRUE(bytes == first) << threads << " threads";
  }
  // The rounds ran: one heap makes another sequence.
  ProgressiveMesh one_heap;
  ASSERT_TRUE(encode(grid, options_for(Loop::kFast), one_heap).ok());
  std::string bytes;
  ASSERT_TRUE(write_pm(one_heap, WriteOptions{}, bytes).ok());
  EXPECT_FALSE(bytes == first);
}

TEST(Attributes, MaterialNamesTheStreamCannotHoldFailBeforeTheWork) {
  Mesh grid = test::seamed_grid(4);
  grid.material_names[1] = std::string("bl\0ue", 5);
  ProgressiveMesh pm;
  Status status = encode(grid, EncodeOptions{}, pm);
  EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(status.message().find("material name 1: a NUL character"), std::string::npos)
      << status.message();
  grid.material_names[1] = std::string(5000, 'x');
  EXPECT_EQ(encode(grid, EncodeOptions{}, pm).code(), ErrorCode::kResourceLimit);
  EncodeOptions geometry_only;
  geometry_only.drop_attributes = true;
  EXPECT_TRUE(encode(grid, geometry_only, pm).ok());
}

TEST(Attributes, InvalidAttributeIndicesAreRefused) {
  Mesh grid = test::seamed_grid(4);
  grid.uv_indices[7] = static_cast<uint32_t>(grid.uv_count());
  ProgressiveMesh pm;
  const Status status = encode(grid, EncodeOptions{}, pm);
  EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(status.message().find("texture coordinate index 7"), std::string::npos)
      << status.message();
}

}  // namespace
}  // namespace pm

// spot.obj (../shared/meshes): a textured cow with UV seams, the acceptance mesh of issue 4.
namespace pm {
namespace {

struct PositionKey {
  uint32_t x, y, z;
  bool operator<(const PositionKey& o) const { return std::tie(x, y, z) < std::tie(o.x, o.y, o.z); }
  bool operator==(const PositionKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
PositionKey key_of(const Mesh& m, uint32_t v) {
  return {bits(m.positions[3 * v]), bits(m.positions[3 * v + 1]), bits(m.positions[3 * v + 2])};
}

// The UV seam edges of a mesh, as pairs of positions.
std::vector<std::pair<PositionKey, PositionKey>> uv_seams_by_position(const Mesh& m) {
  std::vector<std::pair<PositionKey, PositionKey>> out;
  for (const EdgeKey& e : seam_edges(m, &m.uv_indices, &m.uvs, 2))
    out.push_back({key_of(m, e.a), key_of(m, e.b)});
  return out;
}

class SpotByLoop : public ::testing::TestWithParam<Loop> {
 protected:
  void SetUp() override {
    if (!test::shared_meshes_available()) {
      test::warn_no_shared_meshes();
      GTEST_SKIP() << test::kNoSharedMeshesMessage;
    }
    ASSERT_TRUE(read_mesh(test::shared_mesh_path("spot.obj"), spot_).ok());
    ASSERT_TRUE(spot_.has_uvs());
    pm_ = encode_ok(spot_, GetParam());
  }
  Mesh spot_;
  ProgressiveMesh pm_;
};

TEST_P(SpotByLoop, FullDetailGivesEveryFacesTextureCoordinatesBitForBit) {
  EXPECT_TRUE(test::same_attributed_faces(spot_, extract_level(pm_, pm_.split_count())));
}

TEST_P(SpotByLoop, SeamsOfTheLevelsLieOnTheInputsSeamsAndNoTextureTriangleTurnsOver) {
  // The input's seam graph, on positions.
  std::map<PositionKey, std::vector<PositionKey>> seam_graph;
  for (const auto& [a, b] : uv_seams_by_position(spot_)) {
    seam_graph[a].push_back(b);
    seam_graph[b].push_back(a);
  }
  ASSERT_FALSE(seam_graph.empty());
  const Mesh full = extract_level(pm_, pm_.split_count());
  for (double ratio : {0.10, 0.02}) {
    const std::size_t level = level_for_faces(pm_, std::size_t(ratio * spot_.face_count()));
    const Mesh lod = extract_level(pm_, level);
    SCOPED_TRACE(std::to_string(lod.face_count()) + " faces");
    std::set<PositionKey> present;
    for (uint32_t v = 0; v < lod.vertex_count(); ++v) present.insert(key_of(lod, v));
    // Each seam edge a-b of the level stands for a chain of the input's seam edges from a
    // to b through vertices the level has removed.
    const auto seams = uv_seams_by_position(lod);
    EXPECT_FALSE(seams.empty());
    for (const auto& [a, b] : seams) {
      std::set<PositionKey> seen{a};
      std::vector<PositionKey> stack{a};
      bool reached = false;
      while (!stack.empty() && !reached) {
        const PositionKey x = stack.back();
        stack.pop_back();
        for (const PositionKey& y : seam_graph[x]) {
          if (y == b) reached = true;
          if (present.count(y) || !seen.insert(y).second) continue;
          stack.push_back(y);
        }
      }
      EXPECT_TRUE(reached) << "a seam edge of the level crosses the texture away from the input's seams";
    }
    // Face k of a level is face k of full detail, coarser.
    int flipped = 0;
    for (std::size_t f = 0; f < lod.face_count(); ++f) {
      auto area = [](const Mesh& m, std::size_t face) {
        const float* p[3];
        for (int k = 0; k < 3; ++k) p[k] = &m.uvs[2 * m.uv_indices[3 * face + k]];
        return (double(p[1][0]) - p[0][0]) * (double(p[2][1]) - p[0][1]) -
               (double(p[1][1]) - p[0][1]) * (double(p[2][0]) - p[0][0]);
      };
      const double input = area(full, f), now = area(lod, f);
      if (input != 0 && !((input > 0) == (now > 0) && now != 0)) ++flipped;
    }
    EXPECT_EQ(flipped, 0);
  }
}

INSTANTIATE_TEST_SUITE_P(Loops, SpotByLoop,
                         ::testing::Values(Loop::kFast,
                                           Loop::kFastRegions, Loop::kFastSchroeder,
                                           Loop::kFastSchroederRegions),
                         [](const auto& info) { return loop_name(info.param); });

}  // namespace
}  // namespace pm
