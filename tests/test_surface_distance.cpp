// measure_surface_distance against answers known in closed form, and pmdec --compare.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "pm/mesh_io.h"
#include "pm/surface_distance.h"
#include "simplify/geometry.h"
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

// Each Voronoi region of a triangle (Ericson 2005, §5.1.5) at a point whose squared distance
// is exact, and the distance as its root, bit for bit (the searches compare squares and
// take the root of the best alone: kept_points.cpp).
TEST(PointTriangleDistance, EachRegionSquaredAndItsRoot) {
  const Vec3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  const struct {
    Vec3 p;
    double squared;
  } cases[] = {
      {Vec3(-1, -1, 0), 2},    // beyond a
      {Vec3(3, -1, 0), 2},     // beyond b
      {Vec3(-1, 3, 0), 2},     // beyond c
      {Vec3(1, -2, 0), 4},     // beside edge ab
      {Vec3(-3, 1, 0), 9},     // beside edge ac
      {Vec3(2, 2, 0), 2},      // beside edge bc, nearest (1, 1, 0)
      {Vec3(0.5, 0.5, 3), 9},  // above the inside
      {Vec3(0.5, 0.5, 0), 0},  // on it
  };
  for (const auto& k : cases) {
    SCOPED_TRACE(testing::Message() << k.p);
    EXPECT_EQ(point_triangle_squared_distance(k.p, a, b, c), k.squared);
    EXPECT_EQ(point_triangle_distance(k.p, a, b, c), std::sqrt(k.squared));
  }
  // A triangle without area (three points on a line): the nearest of its edges.
  const Vec3 d(4, 0, 0);
  EXPECT_EQ(point_triangle_squared_distance(Vec3(1, 3, 0), a, b, d), 9);
  EXPECT_EQ(point_triangle_squared_distance(Vec3(6, 0, 0), a, b, d), 4);
  EXPECT_EQ(point_segment_squared_distance(Vec3(1, 3, 0), a, b), 9);
  EXPECT_EQ(point_segment_squared_distance(Vec3(-2, 0, 0), a, a), 4);
}

// square_surely_within(): a square at most the bound has a root at most `stop` (the root is
// monotone: the bound's own root is checked), for stops over the normal doubles' range, and
// the bound is below stop's square by only a few units in the last place; below that range
// nothing is sure (-1).
TEST(PointTriangleDistance, ASquareSurelyWithinAStopHasItsRootWithin) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> exponent(-150, 150), mantissa(1, 2);
  for (int i = 0; i < 200000; ++i) {
    const double stop = std::ldexp(mantissa(random), static_cast<int>(exponent(random)));
    const double bound = square_surely_within(stop);
    ASSERT_GT(bound, 0) << stop;
    ASSERT_LE(std::sqrt(bound), stop) << stop;
    // And it gives away little: the square of a root a millionth below stop is under it.
    ASSERT_LT(stop * (1 - 1e-6) * stop * (1 - 1e-6), bound) << stop;
  }
  for (const double stop : {1.0, 0.25, 0.3, 1e-100, 1e100}) {
    const double bound = square_surely_within(stop);
    EXPECT_LE(std::sqrt(bound), stop) << stop;
    EXPECT_GT(std::sqrt(std::nextafter(bound, HUGE_VAL) * (1 + 0x1p-49)), stop) << stop;
  }
  EXPECT_EQ(square_surely_within(0.0), -1.0);
  EXPECT_EQ(square_surely_within(1e-160), -1.0);  // its square is below the normal doubles
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

// The full detail of a .pm has the input's faces in another order, and pmdec --error measures
// against it while users measure against their file: the answers must be the same. Faces
// reversed and each rotated, vertices renumbered: the same maxima and sample count, and RMS
// the same up to the rounding of the face areas' sum.
TEST(SurfaceDistance, TheSameWhateverTheOrderOfFacesVerticesAndCorners) {
  const Mesh sphere = unit_icosphere(3);
  const Mesh coarser = scaled(unit_icosphere(1), 1.02f);
  Mesh shuffled;
  const uint32_t n = uint32_t(sphere.vertex_count());
  shuffled.positions.resize(sphere.positions.size());
  for (uint32_t v = 0; v < n; ++v)  // vertex v becomes n - 1 - v
    for (int k = 0; k < 3; ++k)
      shuffled.positions[3 * (n - 1 - v) + k] = sphere.positions[3 * v + k];
  for (std::size_t f = sphere.face_count(); f-- > 0;) {
    const uint32_t* t = &sphere.triangles[3 * f];
    const int r = int(f % 3);  // a different rotation for each face
    for (int c = 0; c < 3; ++c) shuffled.triangles.push_back(n - 1 - t[(r + c) % 3]);
  }
  const SurfaceDistance a = measure(sphere, coarser), b = measure(shuffled, coarser);
  EXPECT_EQ(a.forward_max, b.forward_max);
  EXPECT_EQ(a.backward_max, b.backward_max);
  EXPECT_EQ(a.samples, b.samples);
  EXPECT_NEAR(a.rms, b.rms, 1e-12 * a.rms);
  const SurfaceDistance c = measure(coarser, sphere), d = measure(coarser, shuffled);
  EXPECT_EQ(c.hausdorff, d.hausdorff);
  EXPECT_EQ(c.samples, d.samples);
}

// The measurement done the slow way, from the contract: the same samples (every vertex used
// by a face, with the first face that uses it; then m x m cells per face, one random point
// in each, from a SplitMix64 stream seeded by the face's positions, taken from the corner
// rotation whose coordinate bits are the smallest), each against every triangle of the other
// mesh. The library must find the very same nearest distances through its hierarchy.
struct BruteForce {
  double max = 0, sum_squared = 0;
  std::size_t count = 0;
};

BruteForce brute_force_one_way(const Mesh& from, const Mesh& to, const DistanceOptions& options,
                               uint64_t stream, double noise_floor) {
  auto position = [](const Mesh& mesh, uint32_t v) {
    return Vec3(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
  };
  auto corner = [&](const Mesh& mesh, std::size_t f, int c) {
    return position(mesh, mesh.triangles[3 * f + c]);
  };
  // The corners from the rotation with the smallest coordinate bits, and their hash.
  auto canonical = [&](std::size_t f, Vec3 out[3], uint64_t& hash) {
    std::array<uint32_t, 9> rotations[3];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        std::memcpy(&rotations[r][3 * c], &from.positions[3 * from.triangles[3 * f + (r + c) % 3]],
                    12);
    const int first = int(std::min_element(rotations, rotations + 3) - rotations);
    hash = 0x9e3779b97f4a7c15ULL;
    for (uint32_t bits : rotations[first]) {
      uint64_t z = (hash ^ bits) + 0x9e3779b97f4a7c15ULL;
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
      hash = z ^ (z >> 31);
    }
    for (int c = 0; c < 3; ++c) out[c] = corner(from, f, (first + c) % 3);
  };
  auto area = [&](std::size_t f) {
    Vec3 c[3];
    uint64_t hash;
    canonical(f, c, hash);
    return 0.5 * area_vector(c[0], c[1], c[2]).norm();
  };
  std::vector<uint32_t> first_face(from.vertex_count(), std::numeric_limits<uint32_t>::max());
  for (std::size_t i = from.triangles.size(); i-- > 0;) first_face[from.triangles[i]] = i / 3;
  double mean_area = 0;
  for (std::size_t f = 0; f < from.face_count(); ++f) mean_area += area(f);
  mean_area /= double(from.face_count());
  BruteForce result;
  auto measure = [&](const Vec3& p) {
    double d = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < to.face_count(); ++t)
      d = std::min(
          d, point_triangle_distance(p, corner(to, t, 0), corner(to, t, 1), corner(to, t, 2)));
    if (d <= noise_floor) d = 0;
    result.max = std::max(result.max, d);
    result.sum_squared += d * d;
    ++result.count;
  };
  uint64_t state = 0;
  auto uniform = [&] {  // SplitMix64 (Steele, Lea and Flood 2014)
    uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return double((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  };
  for (std::size_t f = 0; f < from.face_count(); ++f) {
    Vec3 c[3];
    uint64_t hash;
    canonical(f, c, hash);
    state = stream ^ hash;
    const uint32_t* v = &from.triangles[3 * f];
    for (int c = 0; c < 3; ++c) {
      const bool repeated = (c > 0 && v[c] == v[0]) || (c == 2 && v[2] == v[1]);
      if (first_face[v[c]] == f && !repeated) measure(position(from, v[c]));
    }
    double wanted = options.samples_per_face;
    if (mean_area > 0) wanted = std::max(wanted, wanted * area(f) / mean_area);
    const auto m = std::size_t(std::ceil(std::sqrt(wanted)));
    const Vec3 a = c[0];
    const Vec3 ab = (c[1] - a) / double(m), ac = (c[2] - a) / double(m);
    for (std::size_t i = 0; i < m; ++i) {
      for (std::size_t j = 0; i + j < m; ++j) {
        for (bool downward : {false, true}) {
          if (downward && i + j + 2 > m) continue;
          double r1 = uniform(), r2 = uniform();
          if (r1 + r2 > 1) {
            r1 = 1 - r1;
            r2 = 1 - r2;
          }
          const double u = downward ? double(i + 1) - r1 : double(i) + r1;
          const double w = downward ? double(j) + r1 + r2 : double(j) + r2;
          measure(a + ab * u + ac * w);
        }
      }
    }
  }
  return result;
}

// A copy of `mesh` with every vertex moved by up to `amount` in each coordinate,
// deterministically, so that distances vary from sample to sample.
Mesh jittered(Mesh mesh, float amount) {
  uint32_t state = 12345;
  for (float& x : mesh.positions) {
    state = state * 1664525u + 1013904223u;  // Numerical Recipes' LCG
    x += amount * (float(state >> 8) / float(1 << 24) - 0.5f);
  }
  return mesh;
}

TEST(SurfaceDistance, FindsTheSameNearestTrianglesAsBruteForce) {
  // A fine sphere against a coarse one, both ways, with shuffled-looking face orders and
  // degenerate faces: the fine faces are small next to the coarse triangles (few candidate
  // triangles per face) and the coarse ones large next to the fine triangles (the full
  // hierarchy), so both ways of querying are checked.
  Mesh fine = jittered(unit_icosphere(3), 0.02f);
  std::reverse(fine.triangles.begin(), fine.triangles.end());
  fine.triangles.insert(fine.triangles.end(), {5, 5, 7, 1, 2, 1});  // repeated corners
  const Mesh coarse = scaled(jittered(unit_icosphere(1), 0.05f), 1.01f);
  Mesh offset = square_grid(30, 0);
  offset.positions.insert(offset.positions.end(), {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f});
  offset.triangles.insert(offset.triangles.end(),
                          {uint32_t(offset.vertex_count() - 1), uint32_t(offset.vertex_count() - 2),
                           0});  // a sliver reaching up to the other plane
  const std::pair<Mesh, Mesh> pairs[] = {
      {fine, coarse}, {coarse, fine}, {offset, jittered(square_grid(4, 0.1f), 0.05f)}};
  for (const auto& [reference, other] : pairs) {
    for (unsigned threads : {1u, 2u, 3u}) {
      DistanceOptions options;
      options.threads = threads;
      options.seed = 3;
      const SurfaceDistance d = measure(reference, other, options);
      double largest = 0;
      for (const Mesh* mesh : {&reference, &other})
        for (float x : mesh->positions) largest = std::max(largest, std::abs(double(x)));
      const BruteForce forward =
          brute_force_one_way(reference, other, options, options.seed * 2, 1e-12 * largest);
      const BruteForce backward =
          brute_force_one_way(other, reference, options, options.seed * 2 + 1, 1e-12 * largest);
      EXPECT_EQ(d.forward_max, forward.max);
      EXPECT_EQ(d.backward_max, backward.max);
      EXPECT_EQ(d.samples, forward.count + backward.count);
      // The library sums exactly; the plain sums here are good to about 1e-14.
      EXPECT_NEAR(d.forward_rms, std::sqrt(forward.sum_squared / double(forward.count)),
                  1e-12 * d.forward_rms);
      EXPECT_NEAR(d.backward_rms, std::sqrt(backward.sum_squared / double(backward.count)),
                  1e-12 * d.backward_rms);
    }
  }
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
  // --json (one JSON line per file) and -o - would share standard output; without
  // --compare, an output is still required.
  EXPECT_EQ(run({dir.file("s.pm"), "--json", "-o", "-"}, PMDEC_PATH).exit_code, 2);
  EXPECT_EQ(run({dir.file("s.pm")}, PMDEC_PATH).exit_code, 2);
  // The report goes to standard output, so the mesh cannot.
  EXPECT_EQ(run({dir.file("s.pm"), "--compare", original, "-o", "-"}, PMDEC_PATH).exit_code, 2);
}

}  // namespace
}  // namespace pm
