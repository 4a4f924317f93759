// pm_make_samples: writes the committed sample meshes (samples/*.obj, and the material
// library textured.mtl) into a directory.
//
//   pm_make_samples <output-directory>
//
// Standalone on purpose: it does not link the pm library, so the samples are an input to
// test the library with, not a product of it. The output must be byte-for-byte
// reproducible, because a test regenerates the samples and compares them with the
// committed files. Hence:
//  * positions are computed with +, -, *, / and sqrt only, which IEEE 754 rounds exactly
//    the same everywhere; the sine used for the bumps is our own series (libm's sin may
//    differ in the last bit between platforms);
//  * no fused multiply-add contraction (GCC's default with -std=c++17 is off; the pragma
//    below turns off Clang's), since it would change roundings;
//  * floats are printed with std::to_chars, whose shortest round-trip form is fully
//    specified by the standard;
//  * the lattice-built meshes (block, nonmanifold) use integer coordinates scaled by a
//    power of two, so their positions are exact.
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace {

using Face = std::array<uint32_t, 3>;

// A triangle mesh as written to OBJ: float positions, 0-based vertex indices.
struct SampleMesh {
  std::vector<std::array<float, 3>> positions;
  std::vector<Face> faces;
};

// ---------------------------------------------------------------------------------------
// Output

std::string float_text(float value) {
  if (value == 0) value = 0;  // print -0 as 0: a sign on zero means nothing here
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

bool write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) std::fprintf(stderr, "pm_make_samples: cannot write %s\n", path.c_str());
  return static_cast<bool>(out);
}

// Writes `v x y z` lines then `f a b c` lines (1-based), after the comment lines given.
bool write_obj(const std::string& path, const std::vector<std::string>& comments,
               const SampleMesh& mesh) {
  std::string text;
  for (const std::string& comment : comments) text += "# " + comment + "\n";
  text += "# vertices: " + std::to_string(mesh.positions.size()) +
          ", faces: " + std::to_string(mesh.faces.size()) + "\n";
  for (const auto& p : mesh.positions) {
    text += "v " + float_text(p[0]) + " " + float_text(p[1]) + " " + float_text(p[2]) + "\n";
  }
  for (const Face& f : mesh.faces) {
    text += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " +
            std::to_string(f[2] + 1) + "\n";
  }
  return write_text(path, text);
}

// ---------------------------------------------------------------------------------------
// Deterministic arithmetic

constexpr double kPi = 3.14159265358979323846;

// sin(x) from its Taylor series after reduction to [-pi, pi]: only exactly rounded
// operations, so every platform gets the same bits (accuracy ~1e-13 is plenty for bumps).
double portable_sin(double x) {
  x -= 2 * kPi * std::floor(x / (2 * kPi) + 0.5);
  const double x2 = x * x;
  double term = x, sum = x;
  for (int k = 1; k <= 14; ++k) {
    term *= -x2 / ((2 * k) * (2 * k + 1));
    sum += term;
  }
  return sum;
}

double portable_cos(double x) {
  return portable_sin(x + kPi / 2);
}

struct Vec3 {
  double x, y, z;
};

Vec3 normalized(const Vec3& v) {
  const double length = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  return {v.x / length, v.y / length, v.z / length};
}

std::array<float, 3> to_float(const Vec3& v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

// ---------------------------------------------------------------------------------------
// sphere.obj: an icosphere with low-frequency radial bumps.

SampleMesh make_sphere(int subdivisions) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> points = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                              {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                              {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& p : points) p = normalized(p);
  // Counter-clockwise seen from outside.
  std::vector<Face> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                             {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                             {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                             {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    // Each edge's midpoint is created once (keyed by its sorted end points) and pushed out
    // to the unit sphere; each triangle becomes four.
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoint_of;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto found = midpoint_of.find(key);
      if (found != midpoint_of.end()) return found->second;
      const Vec3 pa = points[a], pb = points[b];
      points.push_back(normalized({pa.x + pb.x, pa.y + pb.y, pa.z + pb.z}));
      const auto index = static_cast<uint32_t>(points.size() - 1);
      midpoint_of.emplace(key, index);
      return index;
    };
    std::vector<Face> finer;
    for (const Face& f : faces) {
      const uint32_t ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]),
                     ca = midpoint(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    faces = std::move(finer);
  }
  SampleMesh mesh;
  for (const Vec3& p : points) {
    // A few smooth bumps (radius within about +-12%) so that simplification has shape to
    // preserve and an error metric has something to measure.
    const double radius = 1 + 0.08 * portable_sin(3 * p.x + 0.4) * portable_sin(2 * p.y + 1.1) +
                          0.04 * portable_cos(4 * p.z - 0.3 * p.x);
    mesh.positions.push_back(to_float({radius * p.x, radius * p.y, radius * p.z}));
  }
  mesh.faces = std::move(faces);
  return mesh;
}

// ---------------------------------------------------------------------------------------
// terrain_holes.obj: a height field with three holes.

SampleMesh make_terrain() {
  constexpr int kSide = 60;  // vertices per side; cells are (kSide - 1)^2
  constexpr double kSpacing = 1.0 / 16;
  // The holes, in cell coordinates, well inside the grid and apart from each other so
  // that each is bounded by its own simple loop.
  auto in_hole = [](int i, int j) {
    const bool first = i >= 8 && i < 18 && j >= 10 && j < 16;
    const bool second = i >= 36 && i < 50 && j >= 8 && j < 13;
    const double di = i + 0.5 - 30, dj = j + 0.5 - 40;
    const bool round = di * di + dj * dj < 7.5 * 7.5;
    return first || second || round;
  };
  // Only vertices used by a kept cell are written, numbered in grid order.
  std::vector<char> used(kSide * kSide, 0);
  for (int j = 0; j + 1 < kSide; ++j) {
    for (int i = 0; i + 1 < kSide; ++i) {
      if (in_hole(i, j)) continue;
      for (int corner :
           {j * kSide + i, j * kSide + i + 1, (j + 1) * kSide + i, (j + 1) * kSide + i + 1}) {
        used[corner] = 1;
      }
    }
  }
  SampleMesh mesh;
  std::vector<uint32_t> index_of(kSide * kSide, 0);
  for (int j = 0; j < kSide; ++j) {
    for (int i = 0; i < kSide; ++i) {
      if (!used[j * kSide + i]) continue;
      const double x = i * kSpacing, y = j * kSpacing;
      const double height = 0.25 * portable_sin(1.3 * x) * portable_cos(0.9 * y) +
                            0.1 * portable_sin(2.1 * x + 1.7 * y);
      index_of[j * kSide + i] = static_cast<uint32_t>(mesh.positions.size());
      mesh.positions.push_back(to_float({x, y, height}));
    }
  }
  for (int j = 0; j + 1 < kSide; ++j) {
    for (int i = 0; i + 1 < kSide; ++i) {
      if (in_hole(i, j)) continue;
      const uint32_t v00 = index_of[j * kSide + i], v10 = index_of[j * kSide + i + 1];
      const uint32_t v01 = index_of[(j + 1) * kSide + i], v11 = index_of[(j + 1) * kSide + i + 1];
      // Counter-clockwise seen from +z (above).
      mesh.faces.push_back({v00, v10, v11});
      mesh.faces.push_back({v00, v11, v01});
    }
  }
  return mesh;
}

// ---------------------------------------------------------------------------------------
// Lattice meshes: corners on integer coordinates, welded by exact position.

using Int3 = std::array<int, 3>;

Int3 operator+(const Int3& a, const Int3& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
Int3 operator-(const Int3& a, const Int3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Int3 operator*(int s, const Int3& a) {
  return {s * a[0], s * a[1], s * a[2]};
}

class LatticeMeshBuilder {
 public:
  // The index of the vertex at p, created on first use (vertices are numbered in order of
  // first use, which keeps the output deterministic).
  uint32_t vertex(const Int3& p) {
    const auto found = index_of_.find(p);
    if (found != index_of_.end()) return found->second;
    const auto index = static_cast<uint32_t>(points_.size());
    points_.push_back(p);
    index_of_.emplace(p, index);
    return index;
  }

  // Adds triangle a b c, ordered so that its normal points along `outward`.
  void add_triangle(const Int3& a, const Int3& b, const Int3& c, const Int3& outward) {
    const Int3 u = b - a, v = c - a;
    const long long nx = 1LL * u[1] * v[2] - 1LL * u[2] * v[1];
    const long long ny = 1LL * u[2] * v[0] - 1LL * u[0] * v[2];
    const long long nz = 1LL * u[0] * v[1] - 1LL * u[1] * v[0];
    const long long along = nx * outward[0] + ny * outward[1] + nz * outward[2];
    if (along >= 0) {
      faces_.push_back({vertex(a), vertex(b), vertex(c)});
    } else {
      faces_.push_back({vertex(a), vertex(c), vertex(b)});
    }
  }

  // Adds a face by vertex indices as given (for deliberately broken faces).
  void add_raw_face(const Face& face) { faces_.push_back(face); }

  enum class Cell { kNone, kFull, kLowerHalf };

  // Tessellates the planar grid origin + i * step_u + j * step_v (0 <= i <= cells_u,
  // 0 <= j <= cells_v). Each cell is split along its diagonal from (i+1, j) to (i, j+1);
  // `cell` chooses per cell: both triangles, only the one at (i, j) (so the region can end
  // on a 45-degree line of lattice diagonals), or none.
  void add_grid(
      const Int3& origin, const Int3& step_u, const Int3& step_v, int cells_u, int cells_v,
      const Int3& outward,
      const std::function<Cell(int, int)>& cell = [](int, int) { return Cell::kFull; }) {
    for (int j = 0; j < cells_v; ++j) {
      for (int i = 0; i < cells_u; ++i) {
        const Cell kind = cell(i, j);
        if (kind == Cell::kNone) continue;
        const Int3 p00 = origin + i * step_u + j * step_v;
        const Int3 p10 = p00 + step_u, p01 = p00 + step_v, p11 = p00 + step_u + step_v;
        add_triangle(p00, p10, p01, outward);
        if (kind == Cell::kFull) add_triangle(p10, p11, p01, outward);
      }
    }
  }

  // A closed axis-aligned box [low, high] with unit cells on each side, facing outwards.
  void add_box(const Int3& low, const Int3& high) {
    const Int3 size = high - low;
    for (int axis = 0; axis < 3; ++axis) {
      const int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
      Int3 step_u{0, 0, 0}, step_v{0, 0, 0}, outward{0, 0, 0};
      step_u[u_axis] = 1;
      step_v[v_axis] = 1;
      for (int side : {0, 1}) {
        Int3 origin = low;
        origin[axis] = side ? high[axis] : low[axis];
        outward[axis] = side ? 1 : -1;
        add_grid(origin, step_u, step_v, size[u_axis], size[v_axis], outward);
      }
    }
  }

  // Positions are lattice coordinates times `scale` (a power of two: exact in float).
  SampleMesh build(float scale) const {
    SampleMesh mesh;
    for (const Int3& p : points_)
      mesh.positions.push_back({p[0] * scale, p[1] * scale, p[2] * scale});
    mesh.faces = faces_;
    return mesh;
  }

 private:
  std::map<Int3, uint32_t> index_of_;
  std::vector<Int3> points_;
  std::vector<Face> faces_;
};

// ---------------------------------------------------------------------------------------
// block_features.obj: a stepped block (L-shaped profile) with one chamfered edge.

SampleMesh make_block() {
  using Cell = LatticeMeshBuilder::Cell;
  // The profile in the x-z plane, counter-clockwise (x right, z up): a 24 x 8 base with a
  // 12 x 8 step on its left, whose top right edge is cut at 45 degrees (4 units).
  // Extruded along y over [0, 12]. All edges are on unit lattice steps, so neighbouring
  // faces' tessellations share their vertices along every edge.
  const std::vector<std::array<int, 2>> profile = {{0, 0},   {24, 0}, {24, 8}, {12, 8},
                                                   {12, 12}, {8, 16}, {0, 16}};
  constexpr int kDepth = 12;
  LatticeMeshBuilder builder;
  // The side walls: one rectangle per profile edge, from the profile edge along y.
  for (std::size_t k = 0; k < profile.size(); ++k) {
    const auto [x0, z0] = profile[k];
    const auto [x1, z1] = profile[(k + 1) % profile.size()];
    const int steps = std::max(std::abs(x1 - x0), std::abs(z1 - z0));
    const Int3 step_u{(x1 - x0) / steps, 0, (z1 - z0) / steps};
    // For a counter-clockwise profile the outside is on the right of each edge.
    const Int3 outward{z1 - z0, 0, x0 - x1};
    builder.add_grid({x0, 0, z0}, step_u, {0, 1, 0}, steps, kDepth, outward);
  }
  // The two end caps: the profile's cells; those crossed by the chamfer x + z = 24 keep
  // only their lower-left triangle.
  auto profile_cell = [](int i, int j) {
    if (j < 8) return Cell::kFull;
    if (i >= 12) return Cell::kNone;
    if (i + j <= 22) return Cell::kFull;
    return i + j == 23 ? Cell::kLowerHalf : Cell::kNone;
  };
  builder.add_grid({0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 24, 16, {0, -1, 0}, profile_cell);
  builder.add_grid({0, kDepth, 0}, {1, 0, 0}, {0, 0, 1}, 24, 16, {0, 1, 0}, profile_cell);
  return builder.build(1.0f / 8);
}

// ---------------------------------------------------------------------------------------
// nonmanifold.obj: the usual ways real files break the manifold assumption, each as its
// own piece (apart in space), so that a test can tell them apart.

SampleMesh make_nonmanifold() {
  LatticeMeshBuilder builder;
  // 1. Two closed 2x2x2 boxes sharing an edge (x = y = 2, z in [0, 2]): its two segments
  //    have four faces each.
  builder.add_box({0, 0, 0}, {2, 2, 2});
  builder.add_box({2, 2, 0}, {4, 4, 2});
  // Two vertices no face uses, between pieces so that readers must keep the numbering.
  builder.vertex({-3, -3, -3});
  builder.vertex({-3, -3, 3});
  // 2. A pinched vertex: two closed square pyramids meeting tip to tip at (10, 0, 3).
  for (int base_z : {0, 6}) {
    const Int3 tip{10, 0, 3};
    const Int3 corners[4] = {{8, -2, base_z}, {12, -2, base_z}, {12, 2, base_z}, {8, 2, base_z}};
    const Int3 base_outward{0, 0, base_z == 0 ? -1 : 1};
    builder.add_triangle(corners[0], corners[1], corners[2], base_outward);
    builder.add_triangle(corners[0], corners[2], corners[3], base_outward);
    for (int k = 0; k < 4; ++k) {
      const Int3& a = corners[k];
      const Int3& b = corners[(k + 1) % 4];
      // Away from the base centre, horizontally, and away from the tip vertically.
      const Int3 outward{a[0] + b[0] - 20, a[1] + b[1], base_z == 0 ? 1 : -1};
      builder.add_triangle(a, b, tip, outward);
    }
  }
  // 3. A fin: a strip of 4 triangles leaning out at 45 degrees from the top front edge of a
  //    closed box, so that each of that edge's two segments has three faces.
  builder.add_box({20, 0, 0}, {22, 2, 2});
  builder.add_grid({20, 0, 2}, {1, 0, 0}, {0, -1, 1}, 2, 1, {0, -1, -1});
  // 4. A sheet of two triangles, with one of them repeated exactly (same indices) and a
  //    degenerate face `f a a b` on its diagonal.
  const Int3 sheet[4] = {{30, 0, 0}, {32, 0, 0}, {32, 2, 0}, {30, 2, 0}};
  builder.add_triangle(sheet[0], sheet[1], sheet[2], {0, 0, 1});
  builder.add_triangle(sheet[0], sheet[2], sheet[3], {0, 0, 1});
  builder.add_triangle(sheet[0], sheet[1], sheet[2], {0, 0, 1});
  builder.add_raw_face(
      {builder.vertex(sheet[0]), builder.vertex(sheet[0]), builder.vertex(sheet[2])});
  return builder.build(1.0f / 4);
}

// ---------------------------------------------------------------------------------------
// textured.obj (+ textured.mtl): a closed vase with every attribute an OBJ mesh carries.
//
// A surface of revolution around z (radius varying with height, so that simplification has
// shape to keep), closed by two flat caps:
//  * texture coordinates in three charts: the body unrolled (u = angle / 2 pi, v = height),
//    each cap as a disk. UV seams: the body's vertical cut (u = 0 and u = 1 at the same
//    vertices) and both rims (body and cap charts meet there);
//  * normals per corner: smooth across the body (one per body vertex, from the surface's
//    derivative), flat on the caps (0 0 -1 and 0 0 1): hard edges at both rims;
//  * a colour per vertex, varying with height and angle, rounded to 1/1000;
//  * two materials, `body` and `caps` (usemtl), from textured.mtl.

// Angles and rings of the vase.
constexpr int kVaseSegments = 64;  // around
constexpr int kVaseRings = 25;     // body vertex rings, bottom rim to top rim
constexpr int kVaseCapRings = 3;   // vertex rings of a cap inside its rim, then the centre

// Radius of the body at height parameter t in [0, 1], and its derivative d radius / d t.
double vase_radius(double t) {
  return 0.6 + 0.2 * portable_sin(3 * t + 0.5) + 0.05 * portable_sin(11 * t);
}
double vase_radius_slope(double t) {
  return 0.6 * portable_cos(3 * t + 0.5) + 0.55 * portable_cos(11 * t);
}

double round_to_thousandths(double value) {
  return std::round(value * 1000) / 1000;
}

std::string textured_obj_text(const std::string& comment) {
  constexpr double kHeight = 2.0;  // z from -1 to 1
  std::string vertices, uvs, normals, body_faces, cap_faces;
  uint32_t vertex_count = 0, uv_count = 0, normal_count = 0, face_count = 0;
  auto add_vertex = [&](double x, double y, double z, double red, double green, double blue) {
    const std::array<float, 3> p = to_float({x, y, z});
    vertices += "v " + float_text(p[0]) + " " + float_text(p[1]) + " " + float_text(p[2]) + " " +
                float_text(static_cast<float>(round_to_thousandths(red))) + " " +
                float_text(static_cast<float>(round_to_thousandths(green))) + " " +
                float_text(static_cast<float>(round_to_thousandths(blue))) + "\n";
    return ++vertex_count;  // 1-based, as faces use it
  };
  auto add_uv = [&](double u, double v) {
    uvs +=
        "vt " + float_text(static_cast<float>(u)) + " " + float_text(static_cast<float>(v)) + "\n";
    return ++uv_count;
  };
  auto add_normal = [&](const Vec3& n) {
    const std::array<float, 3> f = to_float(n);
    normals += "vn " + float_text(f[0]) + " " + float_text(f[1]) + " " + float_text(f[2]) + "\n";
    return ++normal_count;
  };
  struct Corner {
    uint32_t v, t, n;
  };
  auto add_face = [&](std::string& out, const Corner& a, const Corner& b, const Corner& c) {
    out += "f";
    for (const Corner& corner : {a, b, c}) {
      out += " " + std::to_string(corner.v) + "/" + std::to_string(corner.t) + "/" +
             std::to_string(corner.n);
    }
    out += "\n";
    ++face_count;
  };
  auto angle = [](int i) { return 2 * kPi * i / kVaseSegments; };
  auto color_at = [](double t, double theta, double inward) {
    return Vec3{0.35 + 0.55 * t, 0.45 + 0.3 * portable_cos(theta) * (1 - inward),
                0.75 - 0.5 * t + 0.2 * inward};
  };

  // Body: vertex (ring j, segment i), normal per vertex, texture coordinates on a
  // (segments + 1) x rings grid (the last column repeats the first one's vertices at u = 1).
  std::vector<uint32_t> body_vertex(kVaseRings * kVaseSegments);
  std::vector<uint32_t> body_normal(kVaseRings * kVaseSegments);
  std::vector<uint32_t> body_uv(kVaseRings * (kVaseSegments + 1));
  for (int j = 0; j < kVaseRings; ++j) {
    const double t = static_cast<double>(j) / (kVaseRings - 1);
    const double radius = vase_radius(t);
    // Outward normal of (r(z) cos a, r(z) sin a, z): (cos a, sin a, -dr/dz).
    const double slope = vase_radius_slope(t) / kHeight;
    for (int i = 0; i < kVaseSegments; ++i) {
      const double c = portable_cos(angle(i)), s = portable_sin(angle(i));
      const Vec3 color = color_at(t, angle(i), 0);
      body_vertex[j * kVaseSegments + i] =
          add_vertex(radius * c, radius * s, kHeight * t - 1, color.x, color.y, color.z);
      body_normal[j * kVaseSegments + i] = add_normal(normalized({c, s, -slope}));
    }
  }
  for (int j = 0; j < kVaseRings; ++j) {
    for (int i = 0; i <= kVaseSegments; ++i) {
      body_uv[j * (kVaseSegments + 1) + i] =
          add_uv(static_cast<double>(i) / kVaseSegments, 0.6 * j / (kVaseRings - 1));
    }
  }
  auto body_corner = [&](int j, int i) {
    return Corner{body_vertex[j * kVaseSegments + i % kVaseSegments],
                  body_uv[j * (kVaseSegments + 1) + i],
                  body_normal[j * kVaseSegments + i % kVaseSegments]};
  };
  for (int j = 0; j + 1 < kVaseRings; ++j) {
    for (int i = 0; i < kVaseSegments; ++i) {
      // Counter-clockwise seen from outside: around (increasing angle), then up.
      add_face(body_faces, body_corner(j, i), body_corner(j, i + 1), body_corner(j + 1, i + 1));
      add_face(body_faces, body_corner(j, i), body_corner(j + 1, i + 1), body_corner(j + 1, i));
    }
  }

  // Caps: rings shrinking to the centre; ring 0 is the body's rim (shared vertices, own
  // texture coordinates and normal).
  for (int top = 0; top < 2; ++top) {
    const int rim_ring = top ? kVaseRings - 1 : 0;
    const double t = top;
    const double rim_radius = vase_radius(t);
    const double z = kHeight * t - 1;
    const uint32_t normal = add_normal({0, 0, top ? 1.0 : -1.0});
    const double centre_u = top ? 0.75 : 0.25, centre_v = 0.8, chart_radius = 0.18;
    std::vector<uint32_t> ring_vertex(kVaseCapRings * kVaseSegments);
    std::vector<uint32_t> ring_uv(kVaseCapRings * kVaseSegments);
    for (int k = 0; k < kVaseCapRings; ++k) {
      const double scale = 1 - static_cast<double>(k) / kVaseCapRings;
      for (int i = 0; i < kVaseSegments; ++i) {
        const double c = portable_cos(angle(i)), s = portable_sin(angle(i));
        if (k == 0) {
          ring_vertex[i] = body_vertex[rim_ring * kVaseSegments + i];
        } else {
          const Vec3 color = color_at(t, angle(i), 1 - scale);
          ring_vertex[k * kVaseSegments + i] = add_vertex(
              rim_radius * scale * c, rim_radius * scale * s, z, color.x, color.y, color.z);
        }
        // Seen from outside, the bottom chart is mirrored so that it is not inside out.
        const double u = centre_u + chart_radius * scale * (top ? c : -c);
        ring_uv[k * kVaseSegments + i] = add_uv(u, centre_v + chart_radius * scale * s);
      }
    }
    const Vec3 centre_color = color_at(t, 0, 1);
    const Corner centre{add_vertex(0, 0, z, centre_color.x, centre_color.y, centre_color.z),
                        add_uv(centre_u, centre_v), normal};
    auto ring_corner = [&](int k, int i) {
      const int index = k * kVaseSegments + i % kVaseSegments;
      return Corner{ring_vertex[index], ring_uv[index], normal};
    };
    for (int k = 0; k < kVaseCapRings; ++k) {
      for (int i = 0; i < kVaseSegments; ++i) {
        const Corner outer_a = ring_corner(k, i), outer_b = ring_corner(k, i + 1);
        // Counter-clockwise seen from outside: from above for the top cap, below for the
        // bottom one.
        if (k + 1 == kVaseCapRings) {
          if (top) {
            add_face(cap_faces, outer_a, outer_b, centre);
          } else {
            add_face(cap_faces, outer_b, outer_a, centre);
          }
          continue;
        }
        const Corner inner_a = ring_corner(k + 1, i), inner_b = ring_corner(k + 1, i + 1);
        if (top) {
          add_face(cap_faces, outer_a, outer_b, inner_b);
          add_face(cap_faces, outer_a, inner_b, inner_a);
        } else {
          add_face(cap_faces, outer_b, outer_a, inner_a);
          add_face(cap_faces, outer_b, inner_a, inner_b);
        }
      }
    }
  }
  return comment + "# vertices: " + std::to_string(vertex_count) +
         ", faces: " + std::to_string(face_count) +
         ", texture coordinates: " + std::to_string(uv_count) +
         ", normals: " + std::to_string(normal_count) + "\nmtllib textured.mtl\n" + vertices + uvs +
         normals + "usemtl body\n" + body_faces + "usemtl caps\n" + cap_faces;
}

const char kTexturedMtl[] =
    R"(# textured.mtl: generated by pm_make_samples (samples/make_samples.cpp); do not edit.
# The materials of textured.obj. Its texture coordinates lay out three charts (the body
# unrolled, each cap as a disk) but no image comes with it: the materials are plain colours.
newmtl body
Kd 0.8 0.55 0.3

newmtl caps
Kd 0.25 0.3 0.35
)";

// ---------------------------------------------------------------------------------------
// polygons.obj: hand-written, to exercise OBJ readers rather than the algorithms.

const char kPolygonsObj[] =
    R"(# polygons.obj: generated by pm_make_samples (samples/make_samples.cpp); do not edit.
# Exercises OBJ readers: quads and pentagons, the v, v/vt, v//vn and v/vt/vn corner forms,
# negative (relative) indices, comments, blank lines, o/g/s/usemtl/mtllib statements and a
# material library that does not exist. Two objects: a closed pentagonal prism (a house
# with a pitched roof) and a flat quad (a sign). Triangulated: 14 vertices, 18 faces.
mtllib polygons.mtl

o house
# Front wall (z = 0), then back wall (z = -2); each a pentagon.
v 0 0 0
v 2 0 0
v 2 1.5 0
v 1 2.5 0
v 0 1.5 0
v 0 0 -2
v 2 0 -2
v 2 1.5 -2
v 1 2.5 -2
v 0 1.5 -2
vt 0 0
vt 1 0
vt 1 0.6
vt 0.5 1
vt 0 0.6
vn 0 0 1
vn 0 0 -1
vn 0 -1 0
vn 1 0 0
vn -1 0 0
vn 0.70710677 0.70710677 0
vn -0.70710677 0.70710677 0

g walls
usemtl plaster
s off
f 1/1/1 2/2/1 3/3/1 4/4/1 5/5/1
f 6/2/2 10/3/2 9/4/2 8/5/2 7/1/2
f 2//4 7//4 8//4 3//4
# The left wall with indices relative to the last vertex and normal read (-1 = last).
f -10//-3 -6//-3 -1//-3 -5//-3

g floor
usemtl concrete
f 1/1 6/2 7/3 2/4

g roof
usemtl tiles
s 1
f 3 8 9 4
f -7/-4/-1 -2/-3/-1 -1/-2/-1 -6/-1/-1

o sign
# Negative indices now count back from these four vertices.
v 3 0 0
v 4 0 0
v 4 1 0
v 3 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
g sign
usemtl paint
f -4/-4 -3/-3 -2/-2 -1/-1
)";

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <output-directory>\n", argv[0]);
    return 2;
  }
  const std::string directory = argv[1];
  const std::string generated =
      "generated by pm_make_samples (samples/make_samples.cpp); do not edit.";
  bool ok = true;
  ok &= write_obj(directory + "/sphere.obj",
                  {"sphere.obj: " + generated,
                   "A closed genus-0 icosphere (4 subdivisions) with smooth radial bumps."},
                  make_sphere(4));
  ok &= write_obj(directory + "/terrain_holes.obj",
                  {"terrain_holes.obj: " + generated,
                   "An open height field (60 x 60 grid) with two rectangular holes and a round "
                   "one: 4 boundary loops."},
                  make_terrain());
  ok &= write_obj(directory + "/block_features.obj",
                  {"block_features.obj: " + generated,
                   "A closed stepped block: flat faces finely tessellated, sharp 90-degree "
                   "edges and corners, one 45-degree chamfer."},
                  make_block());
  ok &= write_obj(directory + "/nonmanifold.obj",
                  {"nonmanifold.obj: " + generated,
                   "Non-manifold pieces: two boxes sharing an edge (4 faces per edge "
                   "segment); two pyramids tip to tip (pinched vertex);",
                   "a fin on a box edge (3 faces per edge segment); a sheet with a duplicated "
                   "face and a face with a repeated index; 2 unreferenced vertices."},
                  make_nonmanifold());
  ok &= write_text(directory + "/polygons.obj", kPolygonsObj);
  ok &= write_text(directory + "/textured.obj",
                   textured_obj_text("# textured.obj: " + generated + "\n" +
                                     "# A closed vase with texture coordinates (three charts, UV "
                                     "seams), normals per corner (hard\n# edges at the rims), "
                                     "a colour per vertex and two materials (textured.mtl).\n"));
  ok &= write_text(directory + "/textured.mtl", kTexturedMtl);
  return ok ? 0 : 1;
}
