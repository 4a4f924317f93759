// Shared by the libFuzzer targets: invariants checked on whatever the library accepts, and
// the mesh-reader target body. A broken invariant aborts, which libFuzzer reports as a
// crash with the input that caused it.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/mesh.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "pm/progressive_mesh.h"
#include "pm/status.h"
#include "../sorted_moves.h"

namespace pm::fuzz {

[[noreturn]] inline void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz invariant broken: %s\n", what.c_str());
  std::abort();
}

inline void check(bool condition, const char* what) {
  if (!condition) fail(what);
}

// Every error carries a stable code and a message; kInternal means a bug in pm.
inline void check_error(const Status& status, const char* call) {
  if (status.code() == ErrorCode::kInternal || status.message().empty()) {
    fail(std::string(call) + " failed with " + error_code_name(status.code()) + ": '" +
         status.message() + "'");
  }
}

inline void check_mesh(const Mesh& mesh, const char* what) {
  check(mesh.positions.size() % 3 == 0, what);
  for (uint32_t index : mesh.triangles) check(index < mesh.vertex_count(), what);
}

// Faces by corner positions (bit patterns), each rotated to its smallest corner and the list
// sorted: equal lists mean the same faces whatever the vertex numbering and face order.
inline std::vector<std::array<uint32_t, 9>> canonical_faces(const Mesh& mesh) {
  std::vector<std::array<uint32_t, 9>> faces(mesh.face_count());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    std::array<uint32_t, 9> best{};
    for (int start = 0; start < 3; ++start) {
      std::array<uint32_t, 9> rotated;
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = mesh.triangles[3 * f + (start + k) % 3];
        std::memcpy(&rotated[3 * k], &mesh.positions[3 * std::size_t{v}], 12);
      }
      if (start == 0 || rotated < best) best = rotated;
    }
    faces[f] = best;
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

inline bool same_faces(const Mesh& a, const Mesh& b) {
  return canonical_faces(a) == canonical_faces(b);
}

// Faces with everything their corners carry (position, colour, texture coordinate and normal
// bits; ~0 for a missing one) and their material's name, rotated and sorted as above: equal
// lists mean the same attributed faces whatever the numbering of vertices and values.
inline std::vector<std::vector<uint32_t>> attributed_faces(const Mesh& mesh, bool materials) {
  auto bits = [](float x) {
    uint32_t b;
    std::memcpy(&b, &x, 4);
    return b;
  };
  std::vector<std::vector<uint32_t>> faces(mesh.face_count());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    std::vector<uint32_t> corners[3];
    for (int k = 0; k < 3; ++k) {
      const std::size_t c = 3 * f + k, v = mesh.triangles[c];
      for (int i = 0; i < 3; ++i) corners[k].push_back(bits(mesh.positions[3 * v + i]));
      for (uint32_t i = 0; i < mesh.color_components; ++i)
        corners[k].push_back(bits(mesh.colors[mesh.color_components * v + i]));
      for (int i = 0; mesh.has_uvs() && i < 2; ++i)
        corners[k].push_back(mesh.uv_indices[c] == kNoAttribute
                                 ? ~0u
                                 : bits(mesh.uvs[2 * std::size_t{mesh.uv_indices[c]} + i]));
      for (int i = 0; mesh.has_normals() && i < 3; ++i)
        corners[k].push_back(mesh.normal_indices[c] == kNoAttribute
                                 ? ~0u
                                 : bits(mesh.normals[3 * std::size_t{mesh.normal_indices[c]} + i]));
    }
    // The smallest of the three rotations as a whole: with two equal corners, the smallest
    // corner alone would not pick one rotation.
    for (int start = 0; start < 3; ++start) {
      std::vector<uint32_t> rotated;
      for (int k = 0; k < 3; ++k) {
        const auto& corner = corners[(start + k) % 3];
        rotated.insert(rotated.end(), corner.begin(), corner.end());
      }
      if (start == 0 || rotated < faces[f]) faces[f] = std::move(rotated);
    }
    if (materials && mesh.has_materials() && mesh.face_materials[f] != kNoAttribute)
      for (char ch : mesh.material_names[mesh.face_materials[f]]) faces[f].push_back(uint8_t(ch));
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

inline bool same_floats(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

inline bool identical(const ProgressiveMesh& a, const ProgressiveMesh& b) {
  if (a.base_vertex_count != b.base_vertex_count || a.loose_vertex_count != b.loose_vertex_count ||
      !same_floats(a.positions, b.positions) || a.base_faces != b.base_faces ||
      a.moved_faces != b.moved_faces || a.carried_faces != b.carried_faces ||
      a.splits.size() != b.splits.size() || a.welds.size() != b.welds.size()) {
    return false;
  }
  // The attributes, bit for bit.
  if (a.color_components != b.color_components || !same_floats(a.colors, b.colors) ||
      !same_floats(a.uvs, b.uvs) || !same_floats(a.normals, b.normals) ||
      a.material_names != b.material_names || a.material_libraries != b.material_libraries ||
      a.face_uvs != b.face_uvs || a.face_normals != b.face_normals ||
      a.face_materials != b.face_materials || a.moved_uvs != b.moved_uvs ||
      a.moved_normals != b.moved_normals) {
    return false;
  }
  for (std::size_t i = 0; i < a.splits.size(); ++i) {
    const VertexSplit& x = a.splits[i];
    const VertexSplit& y = b.splits[i];
    if (x.u != y.u || x.vl != y.vl || x.vr != y.vr || x.moved_begin != y.moved_begin ||
        x.moved_count != y.moved_count || std::memcmp(&x.error, &y.error, 4) != 0) {
      return false;
    }
  }
  for (std::size_t i = 0; i < a.welds.size(); ++i) {
    if (a.welds[i].copy != b.welds[i].copy || a.welds[i].canonical != b.welds[i].canonical) {
      return false;
    }
  }
  return true;
}

// The level-of-detail API on a valid progressive mesh: requests answer levels in range that
// satisfy them, and extracted levels have the counts faces_at_level/vertices_at_level give.
inline void check_levels(const ProgressiveMesh& pm) {
  const std::size_t full = pm.split_count();
  for (std::size_t level : {std::size_t{0}, full / 2, full}) {
    const Mesh mesh = extract_level(pm, level);
    check_mesh(mesh, "extract_level: face index out of range");
    check(mesh.face_count() == faces_at_level(pm, level), "extract_level: face count");
    check(mesh.vertex_count() == vertices_at_level(pm, level), "extract_level: vertex count");
    const float error = error_at_level(pm, level);
    check(std::isfinite(error) && error >= 0.0f, "error_at_level: not finite or negative");
  }
  const std::size_t full_faces = faces_at_level(pm, full);
  for (std::size_t n : {std::size_t{0}, std::size_t{1}, faces_at_level(pm, full / 2), full_faces,
                        full_faces + 1, SIZE_MAX}) {
    const std::size_t level = level_for_faces(pm, n);
    check(level <= full, "level_for_faces: beyond full detail");
    check(level == full || faces_at_level(pm, level) >= n, "level_for_faces: too few faces");
    const std::size_t by_vertices = level_for_vertices(pm, n);
    check(by_vertices <= full, "level_for_vertices: beyond full detail");
    check(by_vertices == full || vertices_at_level(pm, by_vertices) >= n,
          "level_for_vertices: too few vertices");
  }
  for (double e : {0.0, double(error_at_level(pm, full / 2)), 1e30, -1.0, double(NAN)}) {
    const std::size_t level = level_for_error(pm, e);
    check(level <= full, "level_for_error: beyond full detail");
    check(level == full || error_at_level(pm, level) <= e, "level_for_error: error above bound");
  }
}

// Writing a valid progressive mesh always succeeds and reads back identical.
inline void check_pm_round_trip(const ProgressiveMesh& pm) {
  std::string bytes;
  const Status written = write_pm(pm, WriteOptions{1}, bytes);
  if (!written) fail("write_pm of a valid progressive mesh: " + written.message());
  ProgressiveMesh decoded;
  const Status read = read_pm(bytes, decoded);
  if (!read) fail("read_pm of write_pm's output: " + read.message());
  // Format 2.0 stores moved faces in fan order: compare them as sets.
  check(identical(test::with_sorted_moves(pm), test::with_sorted_moves(decoded)),
        "read_pm(write_pm(pm)) differs from pm");
}

// The bounding-box diagonal, in double as the encoder computes it.
inline double diagonal(const std::vector<float>& positions) {
  if (positions.empty()) return 0;
  double low[3], high[3];
  for (int axis = 0; axis < 3; ++axis) low[axis] = high[axis] = positions[axis];
  for (std::size_t i = 0; i < positions.size(); ++i) {
    low[i % 3] = std::min(low[i % 3], double(positions[i]));
    high[i % 3] = std::max(high[i % 3], double(positions[i]));
  }
  return std::hypot(high[0] - low[0], high[1] - low[1], high[2] - low[2]);
}

// Meshes up to this size are encoded as well: the encoder's repair path sees every oddity the
// readers let through, and each run stays in the milliseconds.
inline constexpr std::size_t kMaxEncodedFaces = 2000;
inline constexpr std::size_t kMaxEncodedVertices = 4000;

inline int fuzz_mesh_reader(const uint8_t* data, std::size_t size, MeshFormat format) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  Mesh mesh;
  ReadReport report;
  const Status status = read_mesh_from_memory(bytes, format, mesh, &report);
  if (!status) {
    check_error(status, "read_mesh_from_memory");
    return 0;
  }
  check_mesh(mesh, "reader: face index out of range");
  {
    std::string problem;
    if (Status valid = validate_attributes(mesh); !valid)
      fail("reader: invalid attributes: " + valid.message());
  }
  for (float x : mesh.positions) check(std::isfinite(x), "reader: non-finite coordinate");

  // The writer's output reads back to the same faces. Not for STL: its reader merges equal
  // positions and drops the faces that makes degenerate, so its round trip is not exact.
  if (format != MeshFormat::kStl) {
    std::string written;
    const Status write = write_mesh_to_memory(mesh, format, written);
    if (!write) {
      check_error(write, "write_mesh_to_memory");
    } else {
      Mesh reread;
      const Status read_back = read_mesh_from_memory(written, format, reread);
      if (!read_back) fail("reading back what the writer wrote: " + read_back.message());
      check(same_faces(mesh, reread), "written and read back: different faces");
      // OFF keeps no materials, and writes a vertex once per combination of its corners'
      // texture coordinates and normals (a seam); the values survive.
      const bool off = format == MeshFormat::kOff;
      check(attributed_faces(mesh, !off) == attributed_faces(reread, !off),
            "written and read back: different corner attributes");
      check(off || reread.vertex_count() == mesh.vertex_count(), "written and read back: vertex count");
    }
  }

  if (mesh.face_count() > kMaxEncodedFaces || mesh.vertex_count() > kMaxEncodedVertices) return 0;
  EncodeOptions options;
  // The last byte picks the loop, so each sees the same inputs: the default loop with either
  // metric, or the collapse loop (geometry only, so attributes are dropped for it).
  const uint8_t last = size > 0 ? data[size - 1] : 0;
  options.metric = last & 1 ? Metric::kQuadric : Metric::kSchroeder;
  if (last & 2) {
    options.fast = true;
    options.metric = Metric::kQuadric;
    options.drop_attributes = true;
  }
  ProgressiveMesh pm;
  const Status encoded = encode(mesh, options, pm);
  if (!encoded) {
    // Only a mesh without vertices (an OBJ of faces alone fails to parse), or one too wide for
    // float32 error bounds, may not encode.
    const bool allowed = (encoded.code() == ErrorCode::kEmptyMesh && mesh.vertex_count() == 0) ||
                         (encoded.code() == ErrorCode::kResourceLimit &&
                          diagonal(mesh.positions) > kMaxEncodeDiagonal) ||
                         !check_material_strings(mesh.material_names, mesh.material_libraries);
    if (!allowed) {
      fail(std::string("encode failed on a mesh the reader accepted: ") +
           error_code_name(encoded.code()) + ": " + encoded.message());
    }
    return 0;
  }
  std::string message;
  if (Status valid = validate(pm); !valid)
    fail("encode produced an invalid progressive mesh: " + valid.message());
  // Nothing is lost: full detail is the input's faces, exactly, with every vertex.
  const Mesh full = extract_level(pm, pm.split_count());
  check(same_faces(mesh, full), "full detail differs from the input's faces");
  check(options.drop_attributes || attributed_faces(mesh, true) == attributed_faces(full, true),
        "full detail differs from the input's corner attributes");
  check(full.vertex_count() == mesh.vertex_count(), "full detail has a different vertex count");
  check_levels(pm);
  check_pm_round_trip(pm);
  return 0;
}

}  // namespace pm::fuzz
