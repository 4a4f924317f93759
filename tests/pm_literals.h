// Literal progressive meshes for the codec tests (test_pm_codec.cpp for format 1.x,
// test_pm_stream.cpp for 2.0), and field-by-field comparison.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "pm/progressive_mesh.h"

namespace pm::literals {

// ---------------------------------------------------------------------------------------
// Literal meshes
// ---------------------------------------------------------------------------------------

// A tetrahedron 0-1-2-3 plus vertex 4, a copy of vertex 1 (welded), refined by two splits:
//
//   split 0 creates 5 from u = 0 (interior: vl = 2, vr = 3); face 1 (0, 2, 3) moves to 5,
//           then appends face 4 = (5, 0, 2) and face 5 = (0, 5, 3).
//   split 1 creates 6 from u = 5 (boundary: vl = none, vr = 3); it moves face 4, which
//           split 0 created, and appends face 6 = (5, 6, 3).
//
// One carried face (2, 2, 3) and two loose vertices (7, 8).
inline ProgressiveMesh small_mesh() {
  ProgressiveMesh pm;
  pm.base_vertex_count = 5;
  pm.loose_vertex_count = 2;
  pm.positions = {
      0.0f,   0.0f,   0.0f,   // 0
      1.0f,   0.0f,   0.0f,   // 1
      0.0f,   1.0f,   0.0f,   // 2
      0.0f,   0.0f,   1.0f,   // 3
      1.0f,   0.0f,   0.0f,   // 4: copy of 1
      -0.5f,  0.5f,   0.25f,  // 5: split 0
      -0.75f, 0.5f,   0.5f,   // 6: split 1
      3.0f,   3.0f,   3.0f,   // 7: loose
      -3.0f,  1e-30f, 1e30f,  // 8: loose
  };
  pm.base_faces = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};
  VertexSplit split0;
  split0.u = 0;
  split0.vl = 2;
  split0.vr = 3;
  split0.error = 0.5f;
  split0.moved_begin = 0;
  split0.moved_count = 1;
  VertexSplit split1;
  split1.u = 5;
  split1.vl = kNoVertex;
  split1.vr = 3;
  split1.error = 0.25f;
  split1.moved_begin = 1;
  split1.moved_count = 1;
  pm.splits = {split0, split1};
  pm.moved_faces = {1, 4};
  pm.welds = {Weld{4, 1}};
  pm.carried_faces = {2, 2, 3};
  return pm;
}

// A single triangle and nothing else: only BASE is written.
inline ProgressiveMesh triangle_mesh() {
  ProgressiveMesh pm;
  pm.base_vertex_count = 3;
  pm.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  pm.base_faces = {0, 1, 2};
  return pm;
}

// A deterministic, larger mesh: a triangle fan refined by `split_count` splits at random
// vertices, so ids pass 127 and 16383 and the varints take 2 and 3 bytes.
inline ProgressiveMesh generated_mesh(uint32_t split_count) {
  uint64_t state = 0x9E3779B97F4A7C15ull;
  auto next = [&state](uint32_t bound) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<uint32_t>((state >> 33) % bound);
  };
  ProgressiveMesh pm;
  const uint32_t ring = 8;
  pm.base_vertex_count = ring + 1;
  for (uint32_t i = 0; i <= ring; ++i) {
    pm.positions.insert(pm.positions.end(), {std::cos(float(i)), std::sin(float(i)), 0.0f});
  }
  for (uint32_t i = 0; i < ring; ++i)
    pm.base_faces.insert(pm.base_faces.end(), {ring, i, (i + 1) % ring});
  std::vector<uint32_t> faces = pm.base_faces;
  float error = 10.0f;
  for (uint32_t i = 0; i < split_count; ++i) {
    const uint32_t v = pm.base_vertex_count + i;
    // u from a random face, so it has faces to move.
    const uint32_t face = next(static_cast<uint32_t>(faces.size() / 3));
    const uint32_t corner = next(3);
    VertexSplit split;
    split.u = faces[3 * face + corner];
    const uint32_t other1 = faces[3 * face + (corner + 1) % 3];
    const uint32_t other2 = faces[3 * face + (corner + 2) % 3];
    split.vl = next(4) == 0 ? kNoVertex : other1;
    split.vr = split.vl == kNoVertex || next(3) != 0 ? other2 : kNoVertex;
    split.error = error;
    error *= 0.999f;
    split.moved_begin = static_cast<uint32_t>(pm.moved_faces.size());
    for (uint32_t f = 0; f < faces.size() / 3; ++f) {
      uint32_t* corners = &faces[3 * f];
      const bool has_u = corners[0] == split.u || corners[1] == split.u || corners[2] == split.u;
      if (has_u && next(2) == 0) {
        pm.moved_faces.push_back(f);
        for (int c = 0; c < 3; ++c) {
          if (corners[c] == split.u) corners[c] = v;
        }
      }
    }
    split.moved_count = static_cast<uint32_t>(pm.moved_faces.size()) - split.moved_begin;
    if (split.vl != kNoVertex) faces.insert(faces.end(), {v, split.u, split.vl});
    if (split.vr != kNoVertex) faces.insert(faces.end(), {split.u, v, split.vr});
    pm.splits.push_back(split);
    pm.positions.insert(pm.positions.end(), {float(next(1000)) / 7.0f, float(i), -1.0f});
  }
  return pm;
}

// small_mesh() with every attribute (pm-format-1.md §5.7-§5.10). Its faces in creation order:
//   base 0 (0, 1, 2), 1 (0, 2, 3), 2 (0, 3, 1), 3 (1, 3, 2); split 0 moves face 1's corner 0
//   to 5 and appends 4 (5, 0, 2), 5 (0, 5, 3); split 1 moves face 4's corner 5 to 6 and
//   appends 6 (5, 6, 3); carried 7 (2, 2, 3).
// UVs are mostly one per vertex (id = vertex), with a seam at vertex 2 of the carried face
// (uv 5) and one corner without (face 3); moved corners take v's uv.
inline ProgressiveMesh attributed_mesh() {
  ProgressiveMesh pm = small_mesh();
  constexpr uint32_t kNone = kNoAttribute;
  pm.color_components = 4;
  for (int i = 0; i < 36; ++i) pm.colors.push_back(float(i) / 32.0f);
  pm.colors[5] = -0.0f;
  pm.colors[6] = std::numeric_limits<float>::quiet_NaN();
  pm.uvs = {0, 0, 1, 0, 0, 1, 1, 1, 0.5f, 0.5f, 0.25f, 0.75f};  // 6 entries
  pm.face_uvs = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, kNone,        // base faces
                 4, 0, 2, 0, 4, 3,                              // split 0's
                 4, 5, 3,                                       // split 1's
                 2, 5, 3};                                      // carried
  pm.moved_uvs = {4, 5};
  pm.normals = {0, 0, 1, 0, 1, 0, 1, 0, 0};                           // 3 entries
  pm.face_normals = {0, 0, 0, 1, 1, 1, 2, 2, 2, kNone, kNone, kNone,  // base faces
                     0, 1, 2, 2, 1, 0,                                // split 0's
                     1, 1, 2,                                         // split 1's
                     0, 0, 0};                                        // carried
  pm.moved_normals = {1, kNone};
  pm.material_names = {"stone", "m\xc3\xa9tal \xe2\x82\xac", ""};  // UTF-8: "métal €"; empty
  pm.material_libraries = {"scene.mtl", "lib/more materials.mtl"};
  pm.face_materials = {0, 0, 1, 1, kNone, 0, 1, 2};
  return pm;
}

// Any valid progressive mesh with synthetic attributes of the right sizes: colours; UVs
// one per vertex with seams (every 7th corner) and gaps (every 11th); normals likewise;
// three materials in runs of five faces.
inline ProgressiveMesh with_attributes(ProgressiveMesh pm) {
  const std::size_t vertices = pm.vertex_count(), faces = pm.total_face_count();
  pm.color_components = 3;
  for (std::size_t v = 0; v < vertices; ++v)
    pm.colors.insert(pm.colors.end(), {float(v) * 0.5f, -float(v), 1.0f / float(v + 1)});
  const uint32_t uv_count = uint32_t(vertices / 2 + 1), normal_count = uint32_t(vertices + 3);
  for (uint32_t i = 0; i < uv_count; ++i) pm.uvs.insert(pm.uvs.end(), {float(i), 0.5f});
  for (uint32_t i = 0; i < normal_count; ++i) pm.normals.insert(pm.normals.end(), {0, 0, float(i)});
  auto id = [](uint32_t vertex, std::size_t n, uint32_t count) {
    if (n % 11 == 0) return kNoAttribute;
    return n % 7 == 0 ? (vertex * 3 + 1) % count : vertex % count;
  };
  // The corners' vertices in creation order.
  std::vector<uint32_t> corners(pm.base_faces);
  for (std::size_t i = 0; i < pm.splits.size(); ++i) {
    const VertexSplit& s = pm.splits[i];
    const uint32_t v = pm.base_vertex_count + uint32_t(i);
    if (s.vl != kNoVertex) corners.insert(corners.end(), {v, s.u, s.vl});
    if (s.vr != kNoVertex) corners.insert(corners.end(), {s.u, v, s.vr});
    for (uint32_t k = s.moved_begin; k < s.moved_begin + s.moved_count; ++k) {
      pm.moved_uvs.push_back(id(v, k + 5, uv_count));
      pm.moved_normals.push_back(id(v, k + 3, normal_count));
    }
  }
  corners.insert(corners.end(), pm.carried_faces.begin(), pm.carried_faces.end());
  for (std::size_t c = 0; c < corners.size(); ++c) {
    pm.face_uvs.push_back(id(corners[c], c, uv_count));
    pm.face_normals.push_back(id(corners[c], c + 2, normal_count));
  }
  pm.material_names = {"red", "green", "blue"};
  pm.material_libraries = {"a.mtl"};
  for (std::size_t f = 0; f < faces; ++f)
    pm.face_materials.push_back(f % 13 == 0 ? kNoAttribute : uint32_t(f / 5 % 3));
  return pm;
}

// small_mesh() as the 1.0 writer wrote it (zstd level 19, before format 1.1): 1.x readers
// must decode it for ever. The frames' bytes are zstd 1.5.4's; any valid frame would do.
inline const std::string& small_mesh_v1_0() {
  static const std::string bytes(
      "\x89\x50\x4d\x45\x53\x48\x0d\x0a\x01\x00\x00\x00\x00\x00\x00\x00"
      "\x05\x00\x00\x00\x04\x00\x00\x00\x02\x00\x00\x00\x02\x00\x00\x00"
      "\x01\x00\x00\x00\x01\x00\x00\x00\x02\x00\x00\x00\x03\x00\x00\x00"
      "\x05\x00\x00\x00\x00\x00\x00\x3f\x00\x00\x00\x00\x00\x00\x00\x00"
      "\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00"
      "\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\xca\xb8\x56\xdc"
      "\x42\x41\x53\x45\x01\x00\x00\x00\x27\x00\x00\x00\x00\x00\x00\x00"
      "\x48\x00\x00\x00\x00\x00\x00\x00\x28\xb5\x2f\xfd\x24\x48\xd5\x00"
      "\x00\x80\x00\x80\x3f\x80\x3f\x01\x02\x00\x02\x03\x00\x03\x01\x01"
      "\x03\x02\x03\x00\xa0\xc0\x33\x1d\x3c\x00\x1b\x5f\xe1\xe8\x08\x53"
      "\x50\x4c\x54\x01\x00\x00\x00\x2d\x00\x00\x00\x00\x00\x00\x00\x2a"
      "\x00\x00\x00\x00\x00\x00\x00\x28\xb5\x2f\xfd\x24\x2a\x05\x01\x00"
      "\x02\x02\x06\x0c\xf0\x59\x03\x5f\x6b\x17\x25\x6c\x90\xb4\x32\x05"
      "\x63\xf4\xab\xc7\xa6\xdf\x05\x00\x44\x46\x09\x01\x00\xda\xae\x13"
      "\x22\xef\xf4\xae\x57\x45\x4c\x44\x01\x00\x00\x00\x0f\x00\x00\x00"
      "\x00\x00\x00\x00\x02\x00\x00\x00\x00\x00\x00\x00\x28\xb5\x2f\xfd"
      "\x24\x02\x11\x00\x00\x04\x01\xd6\xc6\xdc\x26\x43\x41\x52\x59\x01"
      "\x00\x00\x00\x10\x00\x00\x00\x00\x00\x00\x00\x03\x00\x00\x00\x00"
      "\x00\x00\x00\x28\xb5\x2f\xfd\x24\x03\x19\x00\x00\x02\x02\x03\xde"
      "\x72\x8f\x3d\x4c\x4f\x4f\x53\x01\x00\x00\x00\x20\x00\x00\x00\x00"
      "\x00\x00\x00\x18\x00\x00\x00\x00\x00\x00\x00\x28\xb5\x2f\xfd\x24"
      "\x18\x9d\x00\x00\x68\x00\x00\x40\x40\xc0\x60\x42\xa2\x0d\xca\xf2"
      "\x49\x71\x01\x00\x8c\x4b\x04\x88\x58\x7b\x87",
      363);
  return bytes;
}

inline std::string bits_of(const std::vector<float>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
}

// Every field, floats by bit pattern.
inline void expect_identical(const ProgressiveMesh& a, const ProgressiveMesh& b) {
  EXPECT_EQ(a.base_vertex_count, b.base_vertex_count);
  EXPECT_EQ(a.loose_vertex_count, b.loose_vertex_count);
  EXPECT_EQ(bits_of(a.positions), bits_of(b.positions));
  EXPECT_EQ(a.base_faces, b.base_faces);
  ASSERT_EQ(a.splits.size(), b.splits.size());
  for (std::size_t i = 0; i < a.splits.size(); ++i) {
    SCOPED_TRACE("split " + std::to_string(i));
    EXPECT_EQ(a.splits[i].u, b.splits[i].u);
    EXPECT_EQ(a.splits[i].vl, b.splits[i].vl);
    EXPECT_EQ(a.splits[i].vr, b.splits[i].vr);
    EXPECT_EQ(bits_of({a.splits[i].error}), bits_of({b.splits[i].error}));
    EXPECT_EQ(a.splits[i].moved_begin, b.splits[i].moved_begin);
    EXPECT_EQ(a.splits[i].moved_count, b.splits[i].moved_count);
  }
  EXPECT_EQ(a.moved_faces, b.moved_faces);
  ASSERT_EQ(a.welds.size(), b.welds.size());
  for (std::size_t i = 0; i < a.welds.size(); ++i) {
    EXPECT_EQ(a.welds[i].copy, b.welds[i].copy);
    EXPECT_EQ(a.welds[i].canonical, b.welds[i].canonical);
  }
  EXPECT_EQ(a.carried_faces, b.carried_faces);
  EXPECT_EQ(a.color_components, b.color_components);
  EXPECT_EQ(bits_of(a.colors), bits_of(b.colors));
  EXPECT_EQ(bits_of(a.uvs), bits_of(b.uvs));
  EXPECT_EQ(bits_of(a.normals), bits_of(b.normals));
  EXPECT_EQ(a.material_names, b.material_names);
  EXPECT_EQ(a.material_libraries, b.material_libraries);
  EXPECT_EQ(a.face_uvs, b.face_uvs);
  EXPECT_EQ(a.face_normals, b.face_normals);
  EXPECT_EQ(a.face_materials, b.face_materials);
  EXPECT_EQ(a.moved_uvs, b.moved_uvs);
  EXPECT_EQ(a.moved_normals, b.moved_normals);
}

inline bool identical(const ProgressiveMesh& a, const ProgressiveMesh& b) {
  auto same_splits = [&] {
    for (std::size_t i = 0; i < a.splits.size(); ++i) {
      const VertexSplit &x = a.splits[i], &y = b.splits[i];
      if (x.u != y.u || x.vl != y.vl || x.vr != y.vr || x.moved_begin != y.moved_begin ||
          x.moved_count != y.moved_count || bits_of({x.error}) != bits_of({y.error})) {
        return false;
      }
    }
    return true;
  };
  auto same_welds = [&] {
    for (std::size_t i = 0; i < a.welds.size(); ++i) {
      if (a.welds[i].copy != b.welds[i].copy || a.welds[i].canonical != b.welds[i].canonical) {
        return false;
      }
    }
    return true;
  };
  return a.base_vertex_count == b.base_vertex_count &&
         a.loose_vertex_count == b.loose_vertex_count &&
         bits_of(a.positions) == bits_of(b.positions) && a.base_faces == b.base_faces &&
         a.splits.size() == b.splits.size() && same_splits() && a.moved_faces == b.moved_faces &&
         a.welds.size() == b.welds.size() && same_welds() && a.carried_faces == b.carried_faces &&
         a.color_components == b.color_components && bits_of(a.colors) == bits_of(b.colors) &&
         bits_of(a.uvs) == bits_of(b.uvs) && bits_of(a.normals) == bits_of(b.normals) &&
         a.material_names == b.material_names && a.material_libraries == b.material_libraries &&
         a.face_uvs == b.face_uvs && a.face_normals == b.face_normals &&
         a.face_materials == b.face_materials && a.moved_uvs == b.moved_uvs &&
         a.moved_normals == b.moved_normals;
}

}  // namespace pm::literals
