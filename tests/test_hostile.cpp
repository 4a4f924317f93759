// Hostile meshes (issue 9): each gets the defined behaviour the README's "Hostile meshes"
// section documents: an error with a stable code, or a repair that full detail undoes,
// with every level a valid mesh of the input's topology.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <limits>
#include <string>

#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/pm_codec.h"
#include "test_util.h"

namespace pm {
namespace {

Mesh mesh_of(std::vector<float> positions, std::vector<uint32_t> triangles) {
  Mesh m;
  m.positions = std::move(positions);
  m.triangles = std::move(triangles);
  return m;
}

// A bumpy n x n grid of 2 n^2 triangles, vertices from `first` on, shifted by (dx, 0, 0).
void add_grid(Mesh& m, int n, float dx) {
  const uint32_t first = static_cast<uint32_t>(m.vertex_count());
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m.positions.insert(m.positions.end(), {dx + float(i) / n, float(j) / n,
                                             0.1f * std::sin(3.0f * i / n) * std::cos(2.0f * j / n)});
  auto id = [&](int i, int j) { return first + static_cast<uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j),
                                             id(i + 1, j + 1), id(i, j + 1)});
}

// Encodes (through the .pm codec, as pmenc | pmdec) and checks what every hostile input
// that is accepted must give: full detail is the input exactly, and every level has the
// input's topology.
ProgressiveMesh encode_and_check(const Mesh& input, const EncodeOptions& options = {}) {
  ProgressiveMesh direct, pm;
  Status s = encode(input, options, direct);
  EXPECT_TRUE(s.ok()) << s.message();
  std::string bytes;
  EXPECT_TRUE(write_pm(direct, WriteOptions{}, bytes).ok());
  s = read_pm(bytes, pm);
  EXPECT_TRUE(s.ok()) << s.message();
  const Mesh full = extract_level(pm, pm.split_count());
  EXPECT_TRUE(test::same_faces(input, full));
  EXPECT_EQ(full.vertex_count(), input.vertex_count());
  const test::TopologySummary in = test::summarize_topology(input);
  for (std::size_t level = 0; level < pm.split_count(); level += 1 + pm.split_count() / 16) {
    EXPECT_TRUE(test::keeps_topology(in, test::summarize_topology(extract_level(pm, level))))
        << "level " << level;
  }
  return pm;
}

TEST(Hostile, EmptyMeshIsRefused) {
  ProgressiveMesh pm;
  EXPECT_EQ(encode(Mesh{}, EncodeOptions{}, pm).code(), ErrorCode::kEmptyMesh);
}

TEST(Hostile, NonFiniteCoordinatesAreRefusedNamingTheVertex) {
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                    -std::numeric_limits<float>::infinity()}) {
    Mesh m = mesh_of({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2});
    m.positions[4] = bad;
    ProgressiveMesh pm;
    const Status s = encode(m, EncodeOptions{}, pm);
    EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument);
    EXPECT_NE(s.message().find("vertex 2"), std::string::npos) << s.message();
  }
}

TEST(Hostile, IndexOutOfRangeIsRefusedNamingTheFace) {
  const Mesh m = mesh_of({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2, 0, 2, 3});
  ProgressiveMesh pm;
  const Status s = encode(m, EncodeOptions{}, pm);
  EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(s.message().find("face 2"), std::string::npos) << s.message();
}

TEST(Hostile, ASingleFaceIsItsOwnBaseMesh) {
  const ProgressiveMesh pm = encode_and_check(mesh_of({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2}));
  EXPECT_EQ(pm.split_count(), 0u);
  EXPECT_EQ(pm.base_face_count(), 1u);
}

TEST(Hostile, FacesWithARepeatedVertexAreCarriedAtEveryLevel) {
  Mesh m;
  add_grid(m, 8, 0);
  m.triangles.insert(m.triangles.end(), {3, 3, 40, 7, 50, 7, 60, 60, 60});
  const ProgressiveMesh pm = encode_and_check(m);
  EXPECT_EQ(pm.carried_faces.size(), 9u);
  for (std::size_t level : {std::size_t{0}, pm.split_count() / 2}) {
    const Mesh lod = extract_level(pm, level);
    int repeated = 0;
    for (std::size_t f = 0; f < lod.face_count(); ++f) {
      const uint32_t* t = &lod.triangles[3 * f];
      repeated += t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
    }
    EXPECT_EQ(repeated, 3) << "level " << level;
  }
}

TEST(Hostile, FacesThatAreAllCarriedKeepTheirAttributes) {
  // A quad whose first and third corners are one vertex: both fan triangles repeat a vertex,
  // so no face reaches the half-edge mesh (found by fuzz_obj_reader).
  Mesh m = mesh_of({2, 4, 0, 4, 1, 0, 3, 1, 0}, {1, 0, 1, 1, 1, 2});
  m.uvs = {0, 0, 1, 0, 1, 1, 0, 1};
  m.uv_indices = {0, 1, 2, 0, 2, 3};
  m.material_names = {"paint"};
  m.face_materials = {0, 0};
  const ProgressiveMesh pm = encode_and_check(m);
  EXPECT_EQ(pm.base_face_count(), 0u);
  EXPECT_TRUE(test::same_attributed_faces(m, extract_level(pm, 0)));
}

TEST(Hostile, DuplicateFacesAreKeptBothWays) {
  Mesh m;
  add_grid(m, 8, 0);
  // The same face again, and again reversed: edges with three and four faces.
  m.triangles.insert(m.triangles.end(), {m.triangles[30], m.triangles[31], m.triangles[32],
                                         m.triangles[30], m.triangles[32], m.triangles[31]});
  const ProgressiveMesh pm = encode_and_check(m);
  EXPECT_GT(pm.split_count(), 0u);  // the rest of the grid still simplifies
}

TEST(Hostile, ANonManifoldFanIsCutAndWeldedBack) {
  // Two grids touching at one corner vertex (a pinched vertex), and an edge shared by three
  // faces (a fin).
  Mesh m;
  add_grid(m, 6, 0);
  add_grid(m, 6, 1);
  const uint32_t shared = 6, other = 49;  // grid 0's (6, 0) and grid 1's (0, 0)
  for (uint32_t& v : m.triangles)
    if (v == other) v = shared;
  m.positions.insert(m.positions.end(), {0.5f, 0.5f, 1.0f});
  m.triangles.insert(m.triangles.end(), {0, 1, static_cast<uint32_t>(m.vertex_count() - 1)});
  const ProgressiveMesh pm = encode_and_check(m);
  EXPECT_FALSE(pm.welds.empty());
}

// The same pinched fan and fin with materials and texture coordinates, through the collapse
// loop: the repair cuts and welds, the loop keeps the corners and the material border.
TEST(Hostile, MaterialsOnANonManifoldInputGoThroughTheRepairAndTheFastLoop) {
  Mesh m;
  add_grid(m, 6, 0);
  add_grid(m, 6, 1);
  const uint32_t shared = 6, other = 49;
  for (uint32_t& v : m.triangles)
    if (v == other) v = shared;
  m.positions.insert(m.positions.end(), {0.5f, 0.5f, 1.0f});
  m.triangles.insert(m.triangles.end(), {0, 1, static_cast<uint32_t>(m.vertex_count() - 1)});
  // Grid 0 is two materials, split along x = 0.5 (its faces of columns 0-2 and 3-5); grid 1
  // a third, the fin a fourth. Texture coordinates: each corner its vertex's x and y.
  m.material_names = {"left", "right", "far", "fin"};
  for (std::size_t f = 0; f < m.face_count(); ++f) {
    const std::size_t grid_faces = 2 * 6 * 6;
    m.face_materials.push_back(f >= 2 * grid_faces ? 3 : f >= grid_faces ? 2 : (f / 2) % 6 < 3 ? 0 : 1);
  }
  for (std::size_t v = 0; v < m.vertex_count(); ++v)
    m.uvs.insert(m.uvs.end(), {m.positions[3 * v], m.positions[3 * v + 1]});
  m.uv_indices = m.triangles;
  EncodeOptions fast;
  EncodeStats stats;
  ProgressiveMesh direct;
  ASSERT_TRUE(encode(m, fast, direct, &stats).ok());
  EXPECT_TRUE(stats.repair.any());
  const ProgressiveMesh pm = encode_and_check(m, fast);
  EXPECT_FALSE(pm.welds.empty());
  EXPECT_TRUE(test::same_attributed_faces(m, extract_level(pm, pm.split_count())));
  // At every level, the border of the two materials of grid 0 stays on x = 0.5.
  for (std::size_t level = 0; level <= pm.split_count(); ++level) {
    const Mesh lod = extract_level(pm, level);
    std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> edge_materials;
    for (std::size_t f = 0; f < lod.face_count(); ++f)
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = lod.triangles[3 * f + k], b = lod.triangles[3 * f + (k + 1) % 3];
        edge_materials[{std::min(a, b), std::max(a, b)}].push_back(lod.face_materials[f]);
      }
    int border = 0;
    for (const auto& [edge, materials] : edge_materials) {
      if (materials.size() != 2 || materials[0] == materials[1] || materials[0] > 1 ||
          materials[1] > 1)
        continue;
      ++border;
      EXPECT_EQ(lod.positions[3 * edge.first], 0.5f) << "level " << level;
      EXPECT_EQ(lod.positions[3 * edge.second], 0.5f) << "level " << level;
    }
    EXPECT_GT(border, 0) << "level " << level;
  }
}

TEST(Hostile, IsolatedVerticesComeBackAtFullDetailOnly) {
  Mesh m;
  add_grid(m, 6, 0);
  m.positions.insert(m.positions.end(), {5, 5, 5, -5, 0, 1});
  const ProgressiveMesh pm = encode_and_check(m);
  EXPECT_EQ(pm.loose_vertex_count, 2u);
  EXPECT_EQ(extract_level(pm, 0).vertex_count(), pm.base_vertex_count - pm.welds.size());
}

TEST(Hostile, ZeroAreaFacesAreKeptAndNoneIsCreated) {
  Mesh m;
  add_grid(m, 8, 0);
  // Collinear and coincident corners: faces of zero area.
  const uint32_t a = static_cast<uint32_t>(m.vertex_count());
  m.positions.insert(m.positions.end(), {3, 0, 0, 4, 0, 0, 5, 0, 0, 3, 0, 0});
  m.triangles.insert(m.triangles.end(), {a, a + 1, a + 2, a, a + 3, a + 1});
  const ProgressiveMesh pm = encode_and_check(m);
  auto zero_area_faces = [](const Mesh& mesh) {
    int count = 0;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
      const float* p[3];
      for (int k = 0; k < 3; ++k) p[k] = &mesh.positions[3 * mesh.triangles[3 * f + k]];
      const double ux = p[1][0] - p[0][0], uy = p[1][1] - p[0][1], uz = p[1][2] - p[0][2];
      const double vx = p[2][0] - p[0][0], vy = p[2][1] - p[0][1], vz = p[2][2] - p[0][2];
      const double cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx;
      count += cx == 0 && cy == 0 && cz == 0;
    }
    return count;
  };
  for (std::size_t level = 0; level <= pm.split_count(); level += 1 + pm.split_count() / 8)
    EXPECT_LE(zero_area_faces(extract_level(pm, level)), 2) << "level " << level;
}

TEST(Hostile, ManyTinyComponentsEachKeepTheirTopology) {
  // 20,000 separate quads (two triangles each): each becomes one triangle, none vanishes.
  Mesh m;
  for (uint32_t c = 0; c < 20000; ++c) {
    const float x = float(c % 200), y = float(c / 200);
    const uint32_t v = static_cast<uint32_t>(m.vertex_count());
    m.positions.insert(m.positions.end(), {x, y, 0, x + 0.5f, y, 0, x + 0.5f, y + 0.5f, 0.1f, x, y + 0.5f, 0});
    m.triangles.insert(m.triangles.end(), {v, v + 1, v + 2, v, v + 2, v + 3});
  }
  const ProgressiveMesh pm = encode_and_check(m);
  EXPECT_EQ(pm.base_face_count(), 20000u);
  EXPECT_EQ(pm.split_count(), 20000u);
}

}  // namespace
}  // namespace pm
