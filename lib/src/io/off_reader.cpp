// The OFF reader (read_off below: Geomview's "OFF files").
//
// OFF is not read through OpenMesh because its stream reader cannot be made reliable from
// outside: it ignores the header keyword and parses the body by whatever variant (normals,
// colours, binary) the last *file-based* OFF read anywhere in the process detected (so a
// valid file fails after some other code read an NOFF file), it leaves the rest of each
// face line unread (so per-face colours, which OFF allows, shift every following face), and

#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "io/mesh_readers.h"
#include "io/reader_support.h"

namespace pm::detail {

// Reads ASCII OFF as Geomview specifies it ("OFF files", Geomview manual): an optional
// [ST][C][N]OFF keyword line, the counts "vertices faces [edges]" (on that line or the
// next), one vertex per line: x y z, then per the keyword the normal (N: nx ny nz), the colour
// (C: r g b [a]) and the texture coordinate (ST: s t), in that order; one face per line
// (n i1 .. in, 0-based, then an optional colour). '#' starts a comment anywhere. Whatever
// follows the faces is ignored. Errors name the line, like the OBJ reader's.
//
// Colours: 3 or 4 integers 0..255 or 3 or 4 floats 0..1, as the spec's colour specification
// reads. A value like "1" is both, so the choice is made for the whole file: integers (and
// stored as k / 255) when every colour value in it is written as an integer, floats
// otherwise. A vertex with 3 components in a file where others have 4 gets alpha 1.
// Normals and texture coordinates are per vertex; all-NaN values (which our writer puts at
// a vertex whose corners have none) mean none. Per-face colours and values beyond the
// keyword's are not kept and are reported.
Status read_off(std::string_view bytes, Mesh& mesh, ReadReport& report) {
  using detail::NumberResult;
  const char* p = bytes.data();
  const char* const end = p + bytes.size();
  std::size_t line = 0;
  const char* line_begin = p;  // first non-blank of the current line
  const char* line_end = p;    // its '\n' (or the end of the input)
  // Advances to the next line holding more than blanks and a comment.
  auto next_content_line = [&]() {
    while (p != end) {
      ++line;
      const char* eol =
          static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
      if (eol == nullptr) eol = end;
      line_begin = detail::skip_blanks(p, eol);
      line_end = eol;
      p = eol == end ? end : eol + 1;
      if (line_begin != line_end && *line_begin != '#') return true;
    }
    return false;
  };
  auto error = [&line](const std::string& what) {
    return parse_error("line " + std::to_string(line) + ": " + what);
  };
  auto at_line_end = [&line_end](const char* q) { return q == line_end || *q == '#'; };

  if (!next_content_line()) return Status(ErrorCode::kEmptyMesh, "no vertices or faces");
  const char* q = line_begin;
  while (!detail::is_token_end(q, line_end)) ++q;
  const std::string_view keyword(line_begin, static_cast<std::size_t>(q - line_begin));
  const std::string_view off = "OFF";
  if (keyword.size() < off.size() || keyword.substr(keyword.size() - off.size()) != off) {
    return error("not an off file (no OFF header)");
  }
  std::string_view prefix = keyword.substr(0, keyword.size() - off.size());
  const bool has_uvs = prefix.substr(0, 2) == "ST";
  if (has_uvs) prefix.remove_prefix(2);
  const bool has_colors = !prefix.empty() && prefix[0] == 'C';
  if (has_colors) prefix.remove_prefix(1);
  const bool has_normals = !prefix.empty() && prefix[0] == 'N';
  if (has_normals) prefix.remove_prefix(1);
  if (!prefix.empty()) {
    return Status(ErrorCode::kUnsupportedFormat, "line " + std::to_string(line) + ": off variant " +
                                                     std::string(keyword) + " is not supported");
  }
  q = detail::skip_blanks(q, line_end);
  if (!at_line_end(q) &&
      lower_case(std::string_view(
          q, std::min<std::size_t>(6, static_cast<std::size_t>(line_end - q)))) == "binary") {
    return Status(ErrorCode::kUnsupportedFormat, "binary off is not supported");
  }
  if (at_line_end(q)) {
    if (!next_content_line()) return error("missing vertex and face counts");
    q = line_begin;
  }
  int64_t counts[3] = {0, 0, 0};
  int count_count = 0;
  for (; count_count < 3; ++count_count) {
    q = detail::skip_blanks(q, line_end);
    if (at_line_end(q)) break;
    if (detail::parse_int(q, line_end, counts[count_count]) != NumberResult::kOk ||
        !detail::is_token_end(q, line_end) || counts[count_count] < 0) {
      return error("malformed counts (expected: vertices faces edges)");
    }
  }
  if (count_count < 2 || !at_line_end(detail::skip_blanks(q, line_end))) {
    return error("malformed counts (expected: vertices faces edges)");
  }
  const uint64_t vertices = static_cast<uint64_t>(counts[0]);
  const uint64_t faces = static_cast<uint64_t>(counts[1]);
  const uint64_t remaining = static_cast<uint64_t>(end - p);
  if (vertices > std::numeric_limits<uint32_t>::max()) {
    if (vertices > remaining)
      return error("vertex count " + std::to_string(vertices) + " is more than the file holds");
    return Status(ErrorCode::kResourceLimit, "more vertices than 32-bit indices can address");
  }
  if (vertices == 0 && faces == 0) return Status(ErrorCode::kEmptyMesh, "no vertices or faces");

  mesh = Mesh();
  report = ReadReport();
  // Counts are untrusted: reserve no more than the rest of the file can hold (the shortest
  // vertex line is "0 0 0\n", the shortest face line "3 0 0 0\n"); loops end with the lines.
  const uint64_t reserved_vertices = std::min(vertices, remaining / 6 + 1);
  mesh.positions.reserve(3 * reserved_vertices);
  mesh.triangles.reserve(3 * std::min(faces, remaining / 8 + 1));
  // Values per vertex beyond x y z: normal, colour (3 or 4), texture coordinate.
  const int normal_values = has_normals ? 3 : 0;
  const int uv_values = has_uvs ? 2 : 0;
  const int fixed_values = 3 + normal_values + uv_values;
  std::vector<float> normals, uvs;
  std::vector<float> colors;  // 4 per vertex as read; alpha NaN when the vertex gave 3
  if (has_normals) normals.reserve(3 * reserved_vertices);
  if (has_uvs) uvs.reserve(2 * reserved_vertices);
  if (has_colors) colors.reserve(4 * reserved_vertices);
  bool integer_colors = true;  // every colour value so far was written as an integer
  bool any_alpha = false;
  bool extra_values = false;
  constexpr int kMaxValues = 3 + 3 + 4 + 2;
  for (uint64_t v = 0; v < vertices; ++v) {
    if (!next_content_line()) {
      return error("file ends after " + std::to_string(v) + " of " + std::to_string(vertices) +
                   " vertices");
    }
    float values[kMaxValues];
    std::string_view tokens[kMaxValues];
    int count = 0;
    q = line_begin;
    for (;;) {
      q = detail::skip_blanks(q, line_end);
      if (at_line_end(q)) break;
      const char* token_begin = q;
      float value = 0;
      if (const char* problem = detail::coordinate_problem(detail::parse_float(q, line_end, value)))
        return error(problem);
      if (count < kMaxValues) {
        values[count] = value;
        tokens[count] = std::string_view(token_begin, static_cast<std::size_t>(q - token_begin));
      }
      ++count;
    }
    int color_values = 0;
    if (has_colors) {
      color_values = count - fixed_values;
      if (color_values != 3 && color_values != 4) return error("malformed vertex");
    } else if (count < fixed_values) {
      return error("malformed vertex");
    } else if (count > fixed_values) {
      extra_values = true;
    }
    for (int axis = 0; axis < 3; ++axis) {
      if (!std::isfinite(values[axis])) return error("non-finite coordinate");
    }
    mesh.positions.insert(mesh.positions.end(), values, values + 3);
    const float* field = values + 3;
    if (has_normals) {
      if (classify_tuple(field, 3) == TupleKind::kInvalid) return error("non-finite normal");
      normals.insert(normals.end(), field, field + 3);
      field += 3;
    }
    if (has_colors) {
      const std::string_view* color_tokens = tokens + (field - values);
      for (int k = 0; k < color_values; ++k) {
        if (!std::isfinite(field[k])) return error("non-finite colour");
        integer_colors = integer_colors && is_integer_token(color_tokens[k]);
      }
      colors.insert(colors.end(), field, field + color_values);
      if (color_values == 3) colors.push_back(std::numeric_limits<float>::quiet_NaN());
      any_alpha = any_alpha || color_values == 4;
      field += color_values;
    }
    if (has_uvs) {
      if (classify_tuple(field, 2) == TupleKind::kInvalid) {
        return error("non-finite texture coordinate");
      }
      uvs.insert(uvs.end(), field, field + 2);
    }
  }
  if (extra_values) note_ignored(report, "off vertex values beyond the header keyword's");
  std::vector<uint32_t> corners;
  bool face_colors = false;
  for (uint64_t f = 0; f < faces; ++f) {
    if (!next_content_line()) {
      return error("file ends after " + std::to_string(f) + " of " + std::to_string(faces) +
                   " faces");
    }
    q = line_begin;
    int64_t corner_count = 0;
    if (detail::parse_int(q, line_end, corner_count) != NumberResult::kOk ||
        !detail::is_token_end(q, line_end)) {
      return error("malformed face");
    }
    if (corner_count < 3) return error("face with fewer than 3 corners");
    // Each corner takes at least two characters: a bound that keeps a bad count cheap.
    if (corner_count > line_end - q) return error("malformed face");
    corners.clear();
    for (int64_t c = 0; c < corner_count; ++c) {
      q = detail::skip_blanks(q, line_end);
      int64_t index = 0;
      if (detail::parse_int(q, line_end, index) != NumberResult::kOk ||
          !detail::is_token_end(q, line_end)) {
        return error("malformed face");
      }
      if (index < 0 || static_cast<uint64_t>(index) >= vertices) {
        return error("face index " + std::to_string(index) + " out of range (" +
                     std::to_string(vertices) + " vertices)");
      }
      corners.push_back(static_cast<uint32_t>(index));
    }
    // The rest of the line is the face's colour specification.
    if (!at_line_end(detail::skip_blanks(q, line_end))) face_colors = true;
    if (corners.size() > 3) ++report.polygons_triangulated;
    for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
      mesh.triangles.insert(mesh.triangles.end(), {corners[0], corners[i], corners[i + 1]});
    }
  }
  if (face_colors) note_ignored(report, "off face colours");

  if (has_colors) {
    mesh.color_components = any_alpha ? 4 : 3;
    mesh.colors.reserve(mesh.color_components * vertices);
    for (std::size_t v = 0; v < vertices; ++v) {
      for (uint32_t k = 0; k < mesh.color_components; ++k) {
        float value = colors[4 * v + k];
        if (std::isnan(value)) {
          value = 1.0f;  // a 3-component colour among 4-component ones: opaque
        } else if (integer_colors) {
          if (value < 0 || value > 255) {
            return parse_error("vertex " + std::to_string(v) +
                               ": integer colour component out of 0..255");
          }
          value /= 255.0f;  // an exact integer: the same as k / 255.0f
        }
        mesh.colors.push_back(value);
      }
    }
  }
  if (has_normals) {
    attach_per_vertex(normals, 3, mesh.triangles, mesh.normals, mesh.normal_indices);
  }
  if (has_uvs) attach_per_vertex(uvs, 2, mesh.triangles, mesh.uvs, mesh.uv_indices);
  return Status::ok();
}

}  // namespace pm::detail
