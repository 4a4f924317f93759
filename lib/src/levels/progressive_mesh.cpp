// validate(): every invariant that extract_level() and the .pm reader rely on, checked in
// one pass over the record (O(positions + faces + splits + moved faces + welds)). It is run
// on every decoded file, so a hostile stream is rejected here rather than crashing a
// decoder that trusts vertex and face ids.
#include "pm/progressive_mesh.h"

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "levels/validate_decoded.h"

namespace pm {
namespace {

bool fail(std::string* message, std::string text) {
  if (message) *message = std::move(text);
  return false;
}

std::string face_text(const uint32_t* face) {
  return "(" + std::to_string(face[0]) + ", " + std::to_string(face[1]) + ", " +
         std::to_string(face[2]) + ")";
}

bool has_repeated_index(const uint32_t* face) {
  return face[0] == face[1] || face[1] == face[2] || face[0] == face[2];
}

bool check_counts(const ProgressiveMesh& pm, std::string* message) {
  if (pm.positions.size() % 3 != 0) {
    return fail(message, "positions has " + std::to_string(pm.positions.size()) +
                             " floats, not a multiple of 3");
  }
  // 64-bit sums: the counts are 32-bit and their sum must not wrap.
  const uint64_t expected_vertices =
      uint64_t{pm.base_vertex_count} + pm.splits.size() + pm.loose_vertex_count;
  if (pm.positions.size() / 3 != expected_vertices) {
    return fail(message, "positions has " + std::to_string(pm.positions.size() / 3) +
                             " vertices, expected " + std::to_string(expected_vertices) +
                             " (base " + std::to_string(pm.base_vertex_count) + " + splits " +
                             std::to_string(pm.splits.size()) + " + loose " +
                             std::to_string(pm.loose_vertex_count) + ")");
  }
  // Vertex ids are uint32 and kNoVertex must stay free.
  if (expected_vertices >= kNoVertex) {
    return fail(message, std::to_string(expected_vertices) + " vertices exceed 32-bit ids");
  }
  if (pm.base_faces.size() % 3 != 0) {
    return fail(message, "base_faces has " + std::to_string(pm.base_faces.size()) +
                             " indices, not a multiple of 3");
  }
  if (pm.carried_faces.size() % 3 != 0) {
    return fail(message, "carried_faces has " + std::to_string(pm.carried_faces.size()) +
                             " indices, not a multiple of 3");
  }
  return true;
}

bool check_base_faces(const ProgressiveMesh& pm, std::string* message) {
  for (std::size_t f = 0; f < pm.base_face_count(); ++f) {
    const uint32_t* face = &pm.base_faces[3 * f];
    for (int corner = 0; corner < 3; ++corner) {
      if (face[corner] >= pm.base_vertex_count) {
        return fail(message, "base face " + std::to_string(f) + " uses vertex " +
                                 std::to_string(face[corner]) + " of " +
                                 std::to_string(pm.base_vertex_count));
      }
    }
    if (has_repeated_index(face)) {
      return fail(message,
                  "base face " + std::to_string(f) + " " + face_text(face) + " repeats a vertex");
    }
  }
  return true;
}

// The split's own fields, before its faces are looked at.
bool check_split_vertices(const VertexSplit& split, std::size_t i, uint32_t vertex_count,
                          std::string* message) {
  // Built only on failure: this runs once per split of every stream read.
  const auto where = [i] { return "split " + std::to_string(i); };
  if (split.u >= vertex_count) {
    return fail(message, where() + " has u " + std::to_string(split.u) + " of " +
                             std::to_string(vertex_count) + " vertices");
  }
  if (split.vl != kNoVertex && split.vl >= vertex_count) {
    return fail(message, where() + " has vl " + std::to_string(split.vl) + " of " +
                             std::to_string(vertex_count) + " vertices");
  }
  if (split.vr != kNoVertex && split.vr >= vertex_count) {
    return fail(message, where() + " has vr " + std::to_string(split.vr) + " of " +
                             std::to_string(vertex_count) + " vertices");
  }
  if (split.vl == kNoVertex && split.vr == kNoVertex) {
    return fail(message, where() + " has neither vl nor vr");
  }
  // These also guarantee that the new faces (v, u, vl) and (u, v, vr) repeat no index:
  // v is new, so it differs from u, vl and vr.
  if (split.u == split.vl || split.u == split.vr) {
    return fail(message, where() + " has u " + std::to_string(split.u) + " equal to " +
                             (split.u == split.vl ? "vl" : "vr"));
  }
  if (split.vl == split.vr) {
    return fail(message, where() + " has vl equal to vr (" + std::to_string(split.vl) + ")");
  }
  if (!std::isfinite(split.error) || split.error < 0.0f) {
    return fail(message, where() + " has error " + std::to_string(split.error) +
                             ", not a finite value >= 0");
  }
  return true;
}

// Replays the splits on a face array: each moved face must exist and hold u exactly once,
// exactly as extract_level() will find it. Without `replay_faces`, only each split's own
// fields and its moved range (see validate_decoded()).
bool check_splits(const ProgressiveMesh& pm, std::string* message, bool replay_faces = true) {
  std::size_t total_new_faces = 0;
  for (std::size_t i = 0; replay_faces && i < pm.splits.size(); ++i)
    total_new_faces += pm.splits[i].new_face_count();
  // Each face's corners and the last split that moved it (a duplicate check without
  // clearing a set per split), side by side: the moved faces are scattered over the mesh,
  // and one 16-byte record is one cache miss where two arrays were two (this runs on every
  // stream read and every encode).
  struct FaceRecord {
    uint32_t corner[3];
    uint32_t last_mover;
  };
  std::vector<FaceRecord> faces;
  if (replay_faces) faces.reserve(pm.base_face_count() + total_new_faces);
  constexpr std::size_t kFetchAhead = 32;
  for (std::size_t f = 0; replay_faces && f < pm.base_face_count(); ++f) {
    faces.push_back(FaceRecord{
        {pm.base_faces[3 * f], pm.base_faces[3 * f + 1], pm.base_faces[3 * f + 2]}, UINT32_MAX});
  }

  uint64_t next_moved = 0;  // where the next split's moved range must begin
  for (std::size_t i = 0; i < pm.splits.size(); ++i) {
    const VertexSplit& split = pm.splits[i];
    // Built only on failure: this runs once per split of every stream read.
    const auto where = [i] { return "split " + std::to_string(i); };
    const uint32_t v = static_cast<uint32_t>(pm.base_vertex_count + i);
    if (!check_split_vertices(split, i, v, message)) return false;
    if (i > 0 && split.error > pm.splits[i - 1].error) {
      return fail(message, where() + " has error " + std::to_string(split.error) +
                               " above the previous split's " +
                               std::to_string(pm.splits[i - 1].error));
    }
    if (split.moved_begin != next_moved) {
      return fail(message, where() + " moved faces begin at " + std::to_string(split.moved_begin) +
                               ", expected " + std::to_string(next_moved));
    }
    const uint64_t moved_end = uint64_t{split.moved_begin} + split.moved_count;
    if (moved_end > pm.moved_faces.size()) {
      return fail(message, where() + " moved faces end at " + std::to_string(moved_end) + " of " +
                               std::to_string(pm.moved_faces.size()));
    }
    next_moved = moved_end;
    if (!replay_faces) continue;

    const std::size_t face_count = faces.size();
    for (uint64_t k = split.moved_begin; k < moved_end; ++k) {
      // The faces to move are known ahead: fetched that far ahead, their misses overlap.
      if (k + kFetchAhead < pm.moved_faces.size()) {
        const uint32_t ahead = pm.moved_faces[k + kFetchAhead];
        if (ahead < faces.capacity()) __builtin_prefetch(faces.data() + ahead, 1);
      }
      const uint32_t f = pm.moved_faces[k];
      if (f >= face_count) {
        return fail(message, where() + " moves face " + std::to_string(f) + " of " +
                                 std::to_string(face_count));
      }
      FaceRecord& face = faces[f];
      if (face.last_mover == i) {
        return fail(message, where() + " moves face " + std::to_string(f) + " twice");
      }
      face.last_mover = static_cast<uint32_t>(i);
      uint32_t* corner = face.corner;
      const int u_corners =
          (corner[0] == split.u) + (corner[1] == split.u) + (corner[2] == split.u);
      if (u_corners != 1) {
        return fail(message, where() + " moves face " + std::to_string(f) + " " +
                                 face_text(corner) + ", which does not hold u " +
                                 std::to_string(split.u) + " exactly once");
      }
      for (int c = 0; c < 3; ++c) {
        if (corner[c] == split.u) corner[c] = v;
      }
    }
    if (split.vl != kNoVertex) faces.push_back(FaceRecord{{v, split.u, split.vl}, UINT32_MAX});
    if (split.vr != kNoVertex) faces.push_back(FaceRecord{{split.u, v, split.vr}, UINT32_MAX});
  }
  if (next_moved != pm.moved_faces.size()) {
    return fail(message, "the splits move " + std::to_string(next_moved) +
                             " faces but moved_faces has " + std::to_string(pm.moved_faces.size()));
  }
  return true;
}

bool check_welds(const ProgressiveMesh& pm, std::string* message) {
  // Bounded by base_vertex_count, which check_counts() tied to positions.size().
  std::vector<bool> is_copy(pm.base_vertex_count, false);
  for (std::size_t w = 0; w < pm.welds.size(); ++w) {
    const Weld& weld = pm.welds[w];
    const std::string where = "weld " + std::to_string(w);
    if (weld.copy >= pm.base_vertex_count || weld.canonical >= pm.base_vertex_count) {
      return fail(message, where + " (" + std::to_string(weld.copy) + " -> " +
                               std::to_string(weld.canonical) + ") uses a vertex outside the " +
                               std::to_string(pm.base_vertex_count) + " base vertices");
    }
    if (weld.copy == weld.canonical) {
      return fail(message, where + " welds vertex " + std::to_string(weld.copy) + " to itself");
    }
    if (is_copy[weld.copy]) {
      return fail(message, where + " welds vertex " + std::to_string(weld.copy) + " a second time");
    }
    is_copy[weld.copy] = true;
  }
  // A second pass: the canonical may be named as a copy by a later weld.
  for (std::size_t w = 0; w < pm.welds.size(); ++w) {
    if (is_copy[pm.welds[w].canonical]) {
      return fail(message, "weld " + std::to_string(w) + " has canonical vertex " +
                               std::to_string(pm.welds[w].canonical) + ", itself a copy");
    }
  }
  return true;
}

bool check_carried_faces(const ProgressiveMesh& pm, std::string* message) {
  for (std::size_t i = 0; i < pm.carried_faces.size(); ++i) {
    if (pm.carried_faces[i] >= pm.base_vertex_count) {
      return fail(message, "carried face " + std::to_string(i / 3) + " uses vertex " +
                               std::to_string(pm.carried_faces[i]) + " of " +
                               std::to_string(pm.base_vertex_count) + " base vertices");
    }
  }
  return true;
}

// An attribute id array: empty, or exactly expected_size ids, each below count or none.
bool check_attribute_ids(const std::vector<uint32_t>& ids, std::size_t expected_size,
                         std::size_t count, const char* what, std::string* message) {
  if (ids.empty()) return true;
  if (ids.size() != expected_size) {
    return fail(message, std::string(what) + " has " + std::to_string(ids.size()) +
                             " entries, expected " + std::to_string(expected_size));
  }
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] != kNoAttribute && ids[i] >= count) {
      return fail(message, std::string(what) + " entry " + std::to_string(i) + " is " +
                               std::to_string(ids[i]) + " of " + std::to_string(count));
    }
  }
  return true;
}

bool check_attributes(const ProgressiveMesh& pm, std::string* message) {
  if (pm.color_components != 0 && pm.color_components != 3 && pm.color_components != 4) {
    return fail(message, "colours have " + std::to_string(pm.color_components) +
                             " components, not 3 or 4");
  }
  if (pm.colors.size() != std::size_t{pm.color_components} * pm.vertex_count()) {
    return fail(message, "colours hold " + std::to_string(pm.colors.size()) + " values for " +
                             std::to_string(pm.vertex_count()) + " vertices");
  }
  if (pm.uvs.size() % 2 != 0) return fail(message, "texture coordinates: odd value count");
  if (pm.normals.size() % 3 != 0) return fail(message, "normals: value count not a multiple of 3");
  const std::size_t faces = pm.total_face_count();
  const std::size_t moved = pm.moved_faces.size();
  // A kind present on faces is present on every moved corner too, and absent together.
  if (pm.face_uvs.empty() ? !pm.moved_uvs.empty() : pm.moved_uvs.size() != moved)
    return fail(message, "moved_uvs has " + std::to_string(pm.moved_uvs.size()) +
                             " entries for " + std::to_string(moved) + " moved faces");
  if (pm.face_normals.empty() ? !pm.moved_normals.empty() : pm.moved_normals.size() != moved)
    return fail(message, "moved_normals has " + std::to_string(pm.moved_normals.size()) +
                             " entries for " + std::to_string(moved) + " moved faces");
  return check_attribute_ids(pm.face_uvs, 3 * faces, pm.uv_count(), "face_uvs", message) &&
         check_attribute_ids(pm.face_normals, 3 * faces, pm.normal_count(), "face_normals",
                             message) &&
         check_attribute_ids(pm.face_materials, faces, pm.material_names.size(),
                             "face_materials", message) &&
         check_attribute_ids(pm.moved_uvs, pm.moved_uvs.size(), pm.uv_count(), "moved_uvs",
                             message) &&
         check_attribute_ids(pm.moved_normals, pm.moved_normals.size(), pm.normal_count(),
                             "moved_normals", message);
}

// The input's order (keep_order): a bijection of the input's vertices onto the vertices
// full detail outputs (every vertex id but the welded copies), and of its faces onto all
// faces.
bool check_order(const ProgressiveMesh& pm, std::string* message) {
  if (!pm.keeps_order()) return true;
  const std::size_t vertices = pm.vertex_count(), faces = pm.total_face_count();
  if (pm.input_vertices.size() != vertices - pm.welds.size() || pm.input_faces.size() != faces) {
    return fail(message, "the input order has " + std::to_string(pm.input_vertices.size()) +
                             " vertices and " + std::to_string(pm.input_faces.size()) +
                             " faces, full detail " + std::to_string(vertices - pm.welds.size()) +
                             " and " + std::to_string(faces));
  }
  std::vector<bool> seen(vertices, false);
  for (const Weld& weld : pm.welds) seen[weld.copy] = true;  // copies are not output
  for (std::size_t i = 0; i < pm.input_vertices.size(); ++i) {
    const uint32_t v = pm.input_vertices[i];
    if (v >= vertices || seen[v]) {
      return fail(message, "input vertex " + std::to_string(i) + " is vertex " + std::to_string(v) +
                               ", out of range, a welded copy or named twice");
    }
    seen[v] = true;
  }
  seen.assign(faces, false);
  for (std::size_t t = 0; t < pm.input_faces.size(); ++t) {
    const uint32_t f = pm.input_faces[t] / 3;  // and its rotation, pm.input_faces[t] % 3
    if (f >= faces || seen[f]) {
      return fail(message, "input face " + std::to_string(t) + " is face " + std::to_string(f) +
                               ", out of range or named twice");
    }
    seen[f] = true;
  }
  return true;
}

}  // namespace

std::size_t ProgressiveMesh::total_face_count() const {
  std::size_t faces = base_face_count() + carried_faces.size() / 3;
  for (const VertexSplit& s : splits) faces += s.new_face_count();
  return faces;
}

Status validate(const ProgressiveMesh& pm) {
  std::string problem;
  std::string* message = &problem;
  if (check_counts(pm, message) && check_base_faces(pm, message) && check_splits(pm, message) &&
      check_welds(pm, message) && check_carried_faces(pm, message) &&
      check_attributes(pm, message) && check_order(pm, message))
    return Status::ok();
  return Status(ErrorCode::kInvalidArgument, std::move(problem));
}

namespace detail {

bool validate_decoded(const ProgressiveMesh& pm, std::string* message) {
  return check_counts(pm, message) && check_base_faces(pm, message) &&
         check_splits(pm, message, false) && check_welds(pm, message) &&
         check_carried_faces(pm, message) && check_attributes(pm, message) &&
         check_order(pm, message);
}

}  // namespace detail

}  // namespace pm
