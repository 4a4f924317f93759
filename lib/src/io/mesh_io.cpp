// Format detection, file reading and dispatch. OBJ has its own parser (obj_reader.cpp); OFF
// and PLY are parsed here, with their attributes (see read_off and read_ply); STL goes
// through OpenMesh's reader.
//
// OpenMesh's STL reader normally feeds a PolyMesh, whose add_face refuses non-manifold faces
// and so silently drops data. Here it feeds RawMeshImporter instead, which only records the
// vertices and faces it is given, so what the encoder sees is exactly what the file holds.
//
// OpenMesh's stream readers trust their input more than a library reading user files can:
//  - Counts come from headers and drive loops; a garbage count loops for a very long time.
//    The importer therefore ignores reserve() for allocation, caps the number of elements
//    by the input size, and aborts (by throwing through the reader) on the first face that
//    cannot be right.
//  - The STL stream reader reads binary only when told to, and then trusts the triangle
//    count; the type is detected here, and a binary file's size must match its count. Its
//    ASCII reader accepts malformed numbers as garbage coordinates, so ASCII STL is
//    validated first (validate_ascii_stl).
//  - Text numbers are read with iostreams; ours are imbued with the classic locale, but
//    streams OpenMesh makes itself (STL ASCII lines) use the global C++ locale, so a
//    program must not make a locale with a decimal comma global.
// OpenMesh's readers keep state in process-wide singletons, so reads are serialized.
//
// PLY is not read through OpenMesh (any more) because its reader loses attributes: it
// truncates float colours to bytes, reads no per-corner texture coordinates and misplaces
// every later value of a face with any list besides vertex_indices; its header parser loops
// forever without end_header and misplaces binary data after a comment line.
//
// OFF is not read through OpenMesh because its stream reader cannot be made reliable from
// outside: it ignores the header keyword and parses the body by whatever variant (normals,
// colours, binary) the last *file-based* OFF read anywhere in the process detected (so a
// valid file fails after some other code read an NOFF file), it leaves the rest of each
// face line unread (so per-face colours, which OFF allows, shift every following face), and
// it knows neither comments nor counts on the header line.

#include "pm/mesh_io.h"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>  // pulls in the reader registrations of OpenMeshCore
#include <OpenMesh/Core/IO/Options.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <ios>
#include <limits>
#include <locale>
#include <memory>
#include <mutex>
#include <new>
#include <sstream>
#include <string>
#include <system_error>
#include <unordered_map>
#include <utility>
#include <vector>

#include "io/mesh_readers.h"
#include "io/openmesh_logs.h"

namespace pm {
namespace {

std::string lower_case(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

Status parse_error(std::string message) {
  return Status(ErrorCode::kParseError, std::move(message));
}

// ---------------------------------------------------------------------------------------------
// RawMeshImporter

// Thrown by the importer to stop an OpenMesh reader in the middle of a bad file.
struct AbortRead {
  std::string message;
};

class RawMeshImporter final : public OpenMesh::IO::BaseImporter {
 public:
  using VertexHandle = OpenMesh::VertexHandle;
  using FaceHandle = OpenMesh::FaceHandle;
  using HalfedgeHandle = OpenMesh::HalfedgeHandle;
  using EdgeHandle = OpenMesh::EdgeHandle;
  using Vec2f = OpenMesh::Vec2f;
  using Vec3f = OpenMesh::Vec3f;
  using Vec3d = OpenMesh::Vec3d;
  using Vec4f = OpenMesh::Vec4f;
  using Vec3uc = OpenMesh::Vec3uc;
  using Vec4uc = OpenMesh::Vec4uc;
  using StatusInfo = OpenMesh::Attributes::StatusInfo;

  // `max_elements` bounds vertices and face corners: no format stores one in less than a byte.
  RawMeshImporter(std::istream& in, std::size_t max_elements, bool throw_on_stream_failure)
      : in_(in), max_elements_(max_elements), throw_on_stream_failure_(throw_on_stream_failure) {}

  std::vector<float> positions;
  std::vector<int> corners;             // vertex indices of all faces, as received
  std::vector<uint32_t> corner_counts;  // per face
  bool header_counts_known = false;     // reserve() was called
  std::size_t header_vertices = 0;
  std::size_t header_faces = 0;

  // The readers call this once the header is parsed, with its counts.
  void reserve(unsigned int vertices, unsigned int /*edges*/, unsigned int faces) override {
    header_counts_known = true;
    header_vertices = vertices;
    header_faces = faces;
    // From here on a failed extraction means a malformed body: stop right there rather than
    // let the reader loop on with stale values (std::ios_base::failure propagates out).
    if (throw_on_stream_failure_) in_.exceptions(std::ios_base::failbit | std::ios_base::badbit);
  }

  VertexHandle add_vertex(const Vec3f& point) override {
    check_stream();
    if (vertex_count() >= max_elements_ ||
        vertex_count() >= static_cast<std::size_t>(std::numeric_limits<int>::max())) {
      throw AbortRead{"more vertices than the file can hold"};
    }
    positions.insert(positions.end(), {point[0], point[1], point[2]});
    return VertexHandle(static_cast<int>(vertex_count() - 1));
  }
  VertexHandle add_vertex() override { return add_vertex(Vec3f(0.0f, 0.0f, 0.0f)); }
  void set_point(VertexHandle vertex, const Vec3f& point) override {
    check_stream();
    const std::size_t index = static_cast<std::size_t>(vertex.idx());
    if (vertex.idx() < 0 || index >= vertex_count()) throw AbortRead{"invalid vertex handle"};
    std::memcpy(&positions[3 * index], point.data(), 3 * sizeof(float));
  }

  FaceHandle add_face(const VHandles& face) override {
    check_stream();
    const std::size_t face_index = corner_counts.size();
    if (face.size() < 3) {
      throw AbortRead{"face " + std::to_string(face_index) + " has fewer than 3 corners"};
    }
    if (corners.size() + face.size() > max_elements_) {
      throw AbortRead{"more face corners than the file can hold"};
    }
    for (VertexHandle vertex : face) corners.push_back(vertex.idx());
    corner_counts.push_back(static_cast<uint32_t>(face.size()));
    return FaceHandle(static_cast<int>(face_index));
  }

  std::size_t vertex_count() const { return positions.size() / 3; }

  size_t n_vertices() const override { return vertex_count(); }
  size_t n_faces() const override { return corner_counts.size(); }
  size_t n_edges() const override { return 0; }

  // Everything else a reader may hand over: STL's reader hands over facet normals (derived
  // from the corners, so nothing is lost) and nothing else; status and topology are not part
  // of a pm::Mesh.
  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
  FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f>&) override {}
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_normal(VertexHandle, const Vec3f&) override {}
  void set_normal(VertexHandle, const Vec3d&) override {}
  void set_color(VertexHandle, const Vec3uc&) override {}
  void set_color(VertexHandle, const Vec4uc&) override {}
  void set_color(VertexHandle, const Vec3f&) override {}
  void set_color(VertexHandle, const Vec4f&) override {}
  void set_texcoord(VertexHandle, const Vec2f&) override {}
  void set_texcoord(VertexHandle, const Vec3f&) override {}
  void set_status(VertexHandle, const StatusInfo&) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HalfedgeHandle, const Vec2f&) override {}
  void set_texcoord(HalfedgeHandle, const Vec3f&) override {}
  void set_status(HalfedgeHandle, const StatusInfo&) override {}
  void set_color(EdgeHandle, const Vec3uc&) override {}
  void set_color(EdgeHandle, const Vec4uc&) override {}
  void set_color(EdgeHandle, const Vec3f&) override {}
  void set_color(EdgeHandle, const Vec4f&) override {}
  void set_status(EdgeHandle, const StatusInfo&) override {}
  void set_normal(FaceHandle, const Vec3f&) override {}
  void set_normal(FaceHandle, const Vec3d&) override {}
  void set_color(FaceHandle, const Vec3uc&) override {}
  void set_color(FaceHandle, const Vec4uc&) override {}
  void set_color(FaceHandle, const Vec3f&) override {}
  void set_color(FaceHandle, const Vec4f&) override {}
  void set_status(FaceHandle, const StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}

 private:
  // Callbacks after a failed extraction carry stale or default values: never record them.
  void check_stream() const {
    if (in_.fail()) throw AbortRead{"truncated or malformed data"};
  }

  std::istream& in_;
  std::size_t max_elements_;
  bool throw_on_stream_failure_;
};

// Validates what the importer received and turns it into a triangle mesh.
Status build_mesh(RawMeshImporter& raw, Mesh& mesh, ReadReport& report) {
  const std::size_t vertices = raw.vertex_count();
  if (vertices > std::numeric_limits<uint32_t>::max()) {
    return Status(ErrorCode::kResourceLimit, "more vertices than 32-bit indices can address");
  }
  for (std::size_t v = 0; v < vertices; ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      if (!std::isfinite(raw.positions[3 * v + axis])) {
        return parse_error("vertex " + std::to_string(v) + " has a non-finite coordinate");
      }
    }
  }
  mesh.positions = std::move(raw.positions);
  mesh.triangles.clear();
  report = ReadReport();
  std::size_t first_corner = 0;
  for (std::size_t face = 0; face < raw.corner_counts.size(); ++face) {
    const uint32_t count = raw.corner_counts[face];
    const int* corners = raw.corners.data() + first_corner;
    for (uint32_t i = 0; i < count; ++i) {
      if (corners[i] < 0 || static_cast<std::size_t>(corners[i]) >= vertices) {
        return parse_error("face " + std::to_string(face) + " uses vertex " +
                           std::to_string(corners[i]) + " of " + std::to_string(vertices));
      }
    }
    if (count > 3) ++report.polygons_triangulated;
    for (uint32_t i = 1; i + 1 < count; ++i) {
      mesh.triangles.insert(mesh.triangles.end(),
                            {static_cast<uint32_t>(corners[0]), static_cast<uint32_t>(corners[i]),
                             static_cast<uint32_t>(corners[i + 1])});
    }
    first_corner += count;
  }
  if (vertices == 0) return Status(ErrorCode::kEmptyMesh, "no vertices or faces");
  return Status::ok();
}

// ---------------------------------------------------------------------------------------------
// Header tokens

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// Splits a line into blank-separated tokens, up to a '#' comment.
std::vector<std::string_view> split_tokens(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    if (i == line.size() || line[i] == '#') break;
    std::size_t start = i;
    while (i < line.size() && !is_space(line[i]) && line[i] != '#') ++i;
    tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

bool parse_count(std::string_view token, uint64_t& value) {
  auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && ptr == token.data() + token.size();
}

// ---------------------------------------------------------------------------------------------
// Attributes shared by the PLY and OFF readers

// Records a read-but-not-kept property once.
void note_ignored(ReadReport& report, std::string what) {
  for (const std::string& known : report.ignored_properties) {
    if (known == what) return;
  }
  report.ignored_properties.push_back(std::move(what));
}

// Whether a tuple of attribute values means "none" (every value NaN: what our writers put at
// a corner without one). Values that are partly NaN, or infinite, are an error.
enum class TupleKind { kValue, kNone, kInvalid };

TupleKind classify_tuple(const float* values, int dims) {
  int nans = 0;
  for (int d = 0; d < dims; ++d) {
    if (std::isnan(values[d])) {
      ++nans;
    } else if (!std::isfinite(values[d])) {
      return TupleKind::kInvalid;
    }
  }
  if (nans == 0) return TupleKind::kValue;
  return nans == dims ? TupleKind::kNone : TupleKind::kInvalid;
}

// A per-vertex attribute (one tuple of `dims` per vertex, all-NaN for none) as a table and
// per-corner indices: a corner indexes its vertex's entry. Returns the first vertex with an
// invalid tuple, or -1.
int64_t attach_per_vertex(std::vector<float>& values, int dims,
                          const std::vector<uint32_t>& triangles, std::vector<float>& table,
                          std::vector<uint32_t>& indices) {
  const std::size_t vertices = values.size() / dims;
  std::vector<bool> none(vertices, false);
  for (std::size_t v = 0; v < vertices; ++v) {
    float* tuple = &values[v * dims];
    switch (classify_tuple(tuple, dims)) {
      case TupleKind::kValue:
        break;
      case TupleKind::kNone:
        none[v] = true;
        // The table holds finite values only; no corner will index this entry.
        std::fill(tuple, tuple + dims, 0.0f);
        break;
      case TupleKind::kInvalid:
        return static_cast<int64_t>(v);
    }
  }
  indices.resize(triangles.size());
  for (std::size_t c = 0; c < triangles.size(); ++c) {
    indices[c] = none[triangles[c]] ? kNoAttribute : triangles[c];
  }
  table = std::move(values);
  return -1;
}

// Builds a table of distinct values (bit for bit) from per-corner tuples, in order of first
// appearance. Used for per-corner lists (PLY texcoord, corner_normals).
class ValueTable {
 public:
  ValueTable(std::vector<float>& table, int dims) : table_(table), dims_(dims) {}

  uint32_t add(const float* tuple) {
    uint64_t key[2] = {0, 0};
    std::memcpy(key, tuple, sizeof(float) * static_cast<std::size_t>(dims_));
    const auto [it, inserted] =
        ids_.try_emplace(Key{key[0], key[1]}, static_cast<uint32_t>(table_.size() / dims_));
    if (inserted) table_.insert(table_.end(), tuple, tuple + dims_);
    return it->second;
  }
  std::size_t size() const { return table_.size() / dims_; }

 private:
  struct Key {
    uint64_t low, high;
    bool operator==(const Key& other) const { return low == other.low && high == other.high; }
  };
  struct KeyHash {
    std::size_t operator()(const Key& key) const {
      return std::hash<uint64_t>()(key.low * 0x9E3779B97F4A7C15ull ^ key.high);
    }
  };
  std::vector<float>& table_;
  int dims_;
  std::unordered_map<Key, uint32_t, KeyHash> ids_;
};

// Whether a number token is a plain integer ([+-]digits): Geomview's colour specification
// tells 0..255 integers from 0..1 floats by this.
bool is_integer_token(std::string_view token) {
  std::size_t i = 0;
  if (i < token.size() && (token[i] == '+' || token[i] == '-')) ++i;
  if (i == token.size()) return false;
  for (; i < token.size(); ++i) {
    if (token[i] < '0' || token[i] > '9') return false;
  }
  return true;
}

// ---------------------------------------------------------------------------------------------
// OFF

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

// ---------------------------------------------------------------------------------------------
// PLY

// Our own reader for the format Greg Turk defined in 1994 ("The PLY polygon file format"):
// a text header naming elements and their properties, then the elements in ASCII or binary
// (either byte order). OpenMesh's reader is not used for PLY: it truncates float colours to
// bytes, cannot read per-corner texture coordinates (and misreads every later value of a
// face that has any list besides vertex_indices), and trusts its header too much (see the
// notes at the top of this file).
//
// Kept: vertex x y z; colours red green blue [alpha] (also diffuse_red ...): uchar as c / 255,
// ushort as c / 65535, float and double as they are; normals nx ny nz; texture coordinates
// u v, s t, texture_u texture_v or texture_s texture_t; face vertex_indices (or
// vertex_index), MeshLab's per-corner `texcoord` list (u v per corner) and our writer's
// `corner_normals` list (x y z per corner), where an all-NaN tuple is a corner without one;
// materials as our writer stores them (`comment pm_material NAME` lines, face property
// `pm_material`, -1 for none) and `comment pm_mtllib NAME`. Every other property and element
// is read, checked and reported in ReadReport::ignored_properties.

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

bool ply_type_from_name(std::string_view name, PlyType& type) {
  static const std::pair<std::string_view, PlyType> kNames[] = {
      {"char", PlyType::kInt8},      {"int8", PlyType::kInt8},       {"uchar", PlyType::kUint8},
      {"uint8", PlyType::kUint8},    {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUint16},  {"uint16", PlyType::kUint16},   {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},    {"uint", PlyType::kUint32},     {"uint32", PlyType::kUint32},
      {"float", PlyType::kFloat32},  {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64}};
  for (const auto& [known, known_type] : kNames) {
    if (name == known) {
      type = known_type;
      return true;
    }
  }
  return false;
}

std::size_t ply_type_size(PlyType type) {
  switch (type) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 1;
}

bool is_ply_integer(PlyType type) {
  return type != PlyType::kFloat32 && type != PlyType::kFloat64;
}

// What a property is for.
enum class PlyRole {
  kIgnored,
  kX,
  kY,
  kZ,
  kNormalX,
  kNormalY,
  kNormalZ,
  kU,
  kV,
  kRed,
  kGreen,
  kBlue,
  kAlpha,
  kVertexIndices,
  kCornerUvs,
  kCornerNormals,
  kMaterial,
};

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;
  PlyRole role = PlyRole::kIgnored;
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyEncoding { kAscii, kLittleEndian, kBigEndian };

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::kAscii;
  std::vector<PlyElement> elements;
  std::vector<std::string> material_names;      // comment pm_material NAME
  std::vector<std::string> material_libraries;  // comment pm_mtllib NAME
  std::size_t body_offset = 0;
};

// The text of a comment after its keyword, without surrounding blanks, if the comment is
// `comment KEYWORD text`.
bool comment_value(std::string_view line, std::string_view keyword, std::string& value) {
  std::size_t i = 0;
  while (i < line.size() && is_space(line[i])) ++i;
  line.remove_prefix(i);
  if (line.substr(0, 7) != "comment") return false;
  line.remove_prefix(7);
  i = 0;
  while (i < line.size() && is_space(line[i])) ++i;
  if (i == 0) return false;
  line.remove_prefix(i);
  if (line.substr(0, keyword.size()) != keyword) return false;
  line.remove_prefix(keyword.size());
  if (line.empty() || !is_space(line[0])) return false;
  std::size_t first = 0;
  while (first < line.size() && is_space(line[first])) ++first;
  std::size_t last = line.size();
  while (last > first && is_space(line[last - 1])) --last;
  value = std::string(line.substr(first, last - first));
  return !value.empty();
}

// Reads and checks the header. Comments (besides ours), obj_info and unknown lines are
// skipped: some exporters write free text (Blender 2.4x: "Created by Blender3D ...").
Status parse_ply_header(std::string_view bytes, PlyHeader& header) {
  std::size_t pos = 0;
  bool first_line = true;
  bool saw_format = false;
  bool saw_vertex = false;
  bool saw_face = false;
  for (;;) {
    if (pos >= bytes.size()) return parse_error("invalid ply file: header has no end_header");
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string_view::npos) eol = bytes.size();
    const std::string_view line = bytes.substr(pos, eol - pos);
    pos = eol == bytes.size() ? eol : eol + 1;
    if (first_line) {
      const std::vector<std::string_view> tokens = split_tokens(line);
      if (tokens.size() != 1 || lower_case(tokens[0]) != "ply")
        return parse_error("not a valid ply file");
      first_line = false;
      continue;
    }
    std::string value;
    if (comment_value(line, "pm_material", value)) {
      header.material_names.push_back(std::move(value));
      continue;
    }
    if (comment_value(line, "pm_mtllib", value)) {
      header.material_libraries.push_back(std::move(value));
      continue;
    }
    const std::vector<std::string_view> tokens = split_tokens(line);
    if (tokens.empty()) continue;
    const std::string_view keyword = tokens[0];
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      if (saw_format || tokens.size() != 3) return parse_error("invalid ply file: bad format line");
      if (tokens[1] == "ascii") {
        header.encoding = PlyEncoding::kAscii;
      } else if (tokens[1] == "binary_little_endian") {
        header.encoding = PlyEncoding::kLittleEndian;
      } else if (tokens[1] == "binary_big_endian") {
        header.encoding = PlyEncoding::kBigEndian;
      } else {
        return parse_error("invalid ply file: bad format line");
      }
      saw_format = true;
    } else if (keyword == "element") {
      uint64_t count = 0;
      if (!saw_format || tokens.size() != 3 || !parse_count(tokens[2], count)) {
        return parse_error("invalid ply file: bad element line");
      }
      // Every element takes at least a byte; indices are 32-bit.
      if (count > bytes.size() || count > std::numeric_limits<uint32_t>::max()) {
        return parse_error("invalid ply file: element " + std::string(tokens[1]) + " declares " +
                           std::to_string(count) + " items, more than the file holds");
      }
      if (tokens[1] == "vertex" || tokens[1] == "face") {
        bool& seen = tokens[1] == "vertex" ? saw_vertex : saw_face;
        if (seen)
          return parse_error("invalid ply file: element " + std::string(tokens[1]) +
                             " declared twice");
        seen = true;
      }
      header.elements.push_back(PlyElement{std::string(tokens[1]), count, {}});
    } else if (keyword == "property") {
      if (header.elements.empty())
        return parse_error("invalid ply file: property outside an element");
      PlyProperty property;
      if (tokens.size() == 5 && tokens[1] == "list") {
        if (!ply_type_from_name(tokens[2], property.count_type) ||
            !is_ply_integer(property.count_type) || !ply_type_from_name(tokens[3], property.type)) {
          return parse_error("invalid ply file: unsupported list property types");
        }
        property.is_list = true;
        property.name = std::string(tokens[4]);
      } else if (tokens.size() == 3 && ply_type_from_name(tokens[1], property.type)) {
        property.name = std::string(tokens[2]);
      } else {
        return parse_error("invalid ply file: bad property line");
      }
      header.elements.back().properties.push_back(std::move(property));
    }
  }
  if (!saw_format) return parse_error("invalid ply file: no format line");
  header.body_offset = pos;
  return Status::ok();
}

// Gives each property of the vertex and face elements its role, dropping incomplete groups
// (a colour without blue, a normal without nz) and types that cannot mean what the name
// says; everything left without a role is reported.
void assign_ply_roles(PlyHeader& header, ReadReport& report) {
  auto role_of = [](const std::string& element, const PlyProperty& property) {
    if (element == "vertex" && !property.is_list) {
      static const std::pair<std::string_view, PlyRole> kVertexRoles[] = {
          {"x", PlyRole::kX},         {"y", PlyRole::kY},
          {"z", PlyRole::kZ},         {"nx", PlyRole::kNormalX},
          {"ny", PlyRole::kNormalY},  {"nz", PlyRole::kNormalZ},
          {"u", PlyRole::kU},         {"s", PlyRole::kU},
          {"texture_u", PlyRole::kU}, {"texture_s", PlyRole::kU},
          {"v", PlyRole::kV},         {"t", PlyRole::kV},
          {"texture_v", PlyRole::kV}, {"texture_t", PlyRole::kV},
          {"red", PlyRole::kRed},     {"diffuse_red", PlyRole::kRed},
          {"green", PlyRole::kGreen}, {"diffuse_green", PlyRole::kGreen},
          {"blue", PlyRole::kBlue},   {"diffuse_blue", PlyRole::kBlue},
          {"alpha", PlyRole::kAlpha}};
      for (const auto& [name, role] : kVertexRoles) {
        if (property.name == name) return role;
      }
    }
    if (element == "face") {
      if (property.is_list && is_ply_integer(property.type) &&
          (property.name == "vertex_indices" || property.name == "vertex_index")) {
        return PlyRole::kVertexIndices;
      }
      if (property.is_list && property.name == "texcoord") return PlyRole::kCornerUvs;
      if (property.is_list && property.name == "corner_normals") return PlyRole::kCornerNormals;
      if (!property.is_list && is_ply_integer(property.type) && property.name == "pm_material") {
        return PlyRole::kMaterial;
      }
    }
    return PlyRole::kIgnored;
  };
  auto is_color = [](PlyRole role) {
    return role == PlyRole::kRed || role == PlyRole::kGreen || role == PlyRole::kBlue ||
           role == PlyRole::kAlpha;
  };
  for (PlyElement& element : header.elements) {
    if (element.name != "vertex" && element.name != "face") {
      note_ignored(report, "element " + element.name);
      continue;
    }
    // First pass: roles by name; a role claimed twice keeps its first property.
    std::vector<bool> claimed(static_cast<std::size_t>(PlyRole::kMaterial) + 1, false);
    for (PlyProperty& property : element.properties) {
      PlyRole role = role_of(element.name, property);
      // Colours are bytes (0..255), 16-bit (0..65535) or floats; other types have no scale.
      if (is_color(role) && property.type != PlyType::kUint8 && property.type != PlyType::kUint16 &&
          is_ply_integer(property.type)) {
        role = PlyRole::kIgnored;
      }
      if (role != PlyRole::kIgnored && claimed[static_cast<std::size_t>(role)])
        role = PlyRole::kIgnored;
      if (role != PlyRole::kIgnored) claimed[static_cast<std::size_t>(role)] = true;
      property.role = role;
    }
    auto has = [&claimed](PlyRole role) { return claimed[static_cast<std::size_t>(role)]; };
    // Second pass: groups must be complete; per-corner lists win over per-vertex values.
    const bool normals = has(PlyRole::kNormalX) && has(PlyRole::kNormalY) && has(PlyRole::kNormalZ);
    const bool uvs = has(PlyRole::kU) && has(PlyRole::kV);
    const bool colors = has(PlyRole::kRed) && has(PlyRole::kGreen) && has(PlyRole::kBlue);
    for (PlyProperty& property : element.properties) {
      const PlyRole role = property.role;
      if ((role == PlyRole::kNormalX || role == PlyRole::kNormalY || role == PlyRole::kNormalZ) &&
          !normals) {
        property.role = PlyRole::kIgnored;
      }
      if ((role == PlyRole::kU || role == PlyRole::kV) && !uvs) property.role = PlyRole::kIgnored;
      if (is_color(role) && !colors) property.role = PlyRole::kIgnored;
      if (property.role == PlyRole::kIgnored)
        note_ignored(report, element.name + "." + property.name);
    }
  }
  // A face list of texture coordinates (normals) makes per-vertex ones redundant.
  bool corner_uvs = false, corner_normals = false;
  for (const PlyElement& element : header.elements) {
    if (element.name != "face") continue;
    for (const PlyProperty& property : element.properties) {
      corner_uvs = corner_uvs || property.role == PlyRole::kCornerUvs;
      corner_normals = corner_normals || property.role == PlyRole::kCornerNormals;
    }
  }
  for (PlyElement& element : header.elements) {
    if (element.name != "vertex") continue;
    for (PlyProperty& property : element.properties) {
      const PlyRole role = property.role;
      if ((corner_uvs && (role == PlyRole::kU || role == PlyRole::kV)) ||
          (corner_normals &&
           (role == PlyRole::kNormalX || role == PlyRole::kNormalY || role == PlyRole::kNormalZ))) {
        property.role = PlyRole::kIgnored;
        note_ignored(report, element.name + "." + property.name);
      }
    }
  }
}

// Reads the values of a PLY body one at a time, bounds-checked: numbers separated by white
// space (ASCII), or packed in either byte order (binary). For read_ply's fixed-layout loops
// it also decodes binary values at a given place, which those loops have bounds-checked.
class PlyValueReader {
 public:
  PlyValueReader(std::string_view body, PlyEncoding encoding)
      : p_(body.data()), end_(body.data() + body.size()), encoding_(encoding) {}

  // A value of `type` as a double (which holds every PLY scalar exactly). False at the end of
  // the data or on a malformed ASCII number; `integral` values must be whole numbers.
  bool read(PlyType type, double& value) {
    if (encoding_ != PlyEncoding::kAscii) return read_binary(type, value);
    while (p_ != end_ && is_ascii_space(*p_)) ++p_;
    const char* token_end = p_;
    while (token_end != end_ && !is_ascii_space(*token_end)) ++token_end;
    if (token_end == p_) return false;
    const char* q = p_;
    p_ = token_end;
    if (type == PlyType::kFloat32) {
      // Parsed as float32 directly: through a double could round twice.
      float single = 0;
      if (detail::parse_float(q, token_end, single) != detail::NumberResult::kOk || q != token_end)
        return false;
      value = single;
      return true;
    }
    if (type == PlyType::kFloat64) {
      if (q != token_end && *q == '+') ++q;
      auto [ptr, ec] = std::from_chars(q, token_end, value);
      return ec == std::errc() && ptr == token_end;
    }
    int64_t integer = 0;
    if (detail::parse_int(q, token_end, integer) != detail::NumberResult::kOk || q != token_end)
      return false;
    if (!integer_fits(type, integer)) return false;
    value = static_cast<double>(integer);
    return true;
  }

  // Bytes left (binary) or characters left (ASCII): a bound on how many values can follow.
  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }
  bool is_binary() const { return encoding_ != PlyEncoding::kAscii; }

  // For the fixed-layout loops of read_ply, which check the bounds of a whole item at once:
  // the binary value of `type` at `at`, without a bounds check.
  double decode(PlyType type, const char* at) const {
    switch (type) {
      case PlyType::kFloat32: {
        const uint32_t bits = load<uint32_t>(at);
        float single;
        std::memcpy(&single, &bits, sizeof single);
        return single;
      }
      case PlyType::kFloat64: {
        const uint64_t bits = load<uint64_t>(at);
        double wide;
        std::memcpy(&wide, &bits, sizeof wide);
        return wide;
      }
      default:  // every integer type is exact in a double
        return static_cast<double>(decode_integer(type, at));
    }
  }
  // The same for an integer type (not a float one), without going through a double.
  int64_t decode_integer(PlyType type, const char* at) const {
    switch (type) {
      case PlyType::kInt8:
        return static_cast<int8_t>(at[0]);
      case PlyType::kUint8:
        return static_cast<uint8_t>(at[0]);
      case PlyType::kInt16:
        return static_cast<int16_t>(load<uint16_t>(at));
      case PlyType::kUint16:
        return load<uint16_t>(at);
      case PlyType::kInt32:
        return static_cast<int32_t>(load<uint32_t>(at));
      case PlyType::kUint32:
        return load<uint32_t>(at);
      case PlyType::kFloat32:
      case PlyType::kFloat64:
        break;
    }
    return 0;
  }
  const char* cursor() const { return p_; }
  void skip(std::size_t bytes) { p_ += bytes; }

 private:
  static bool is_ascii_space(char c) { return c == '\n' || is_space(c); }

  static bool integer_fits(PlyType type, int64_t value) {
    switch (type) {
      case PlyType::kInt8:
        return value >= -128 && value <= 127;
      case PlyType::kUint8:
        return value >= 0 && value <= 255;
      case PlyType::kInt16:
        return value >= -32768 && value <= 32767;
      case PlyType::kUint16:
        return value >= 0 && value <= 65535;
      case PlyType::kInt32:
        return value >= std::numeric_limits<int32_t>::min() &&
               value <= std::numeric_limits<int32_t>::max();
      case PlyType::kUint32:
        return value >= 0 && value <= std::numeric_limits<uint32_t>::max();
      default:
        return true;
    }
  }

  bool read_binary(PlyType type, double& value) {
    const std::size_t size = ply_type_size(type);
    if (remaining() < size) return false;
    value = decode(type, p_);
    p_ += size;
    return true;
  }

  static bool host_is_little_endian() {
    const uint16_t probe = 1;
    unsigned char first;
    std::memcpy(&first, &probe, 1);
    return first == 1;
  }

  // An unsigned integer of the file's byte order: one load, and a byte swap when the host's
  // order differs.
  template <typename Unsigned>
  Unsigned load(const char* at) const {
    Unsigned bits;
    std::memcpy(&bits, at, sizeof bits);
    if (swap_) {
      unsigned char bytes[sizeof bits];
      std::memcpy(bytes, &bits, sizeof bits);
      std::reverse(bytes, bytes + sizeof bits);
      std::memcpy(&bits, bytes, sizeof bits);
    }
    return bits;
  }

  const char* p_;
  const char* end_;
  PlyEncoding encoding_;
  bool swap_ = encoding_ != PlyEncoding::kAscii &&
               (encoding_ == PlyEncoding::kLittleEndian) != host_is_little_endian();
};

// A PLY value as float32, rounded to nearest; beyond float's range it is infinite (which the
// callers reject) rather than the undefined behaviour of converting it directly.
float narrow_to_float(double value) {
  // FLT_MAX plus half an ulp: from here on, round to nearest gives infinity.
  constexpr double kOverflow = 0x1.ffffffp127;
  if (std::fabs(value) >= kOverflow) {
    return value > 0 ? std::numeric_limits<float>::infinity()
                     : -std::numeric_limits<float>::infinity();
  }
  return static_cast<float>(value);
}

// A colour component as the mesh stores it.
float ply_color(PlyType type, double value) {
  if (type == PlyType::kUint8) return static_cast<float>(value) / 255.0f;
  if (type == PlyType::kUint16) return static_cast<float>(value) / 65535.0f;
  return narrow_to_float(value);
}

Status read_ply(std::string_view bytes, Mesh& mesh, ReadReport& report) {
  PlyHeader header;
  if (Status status = parse_ply_header(bytes, header); !status) return status;
  report = ReadReport();
  assign_ply_roles(header, report);
  mesh = Mesh();
  mesh.material_libraries = header.material_libraries;

  PlyValueReader reader(bytes.substr(header.body_offset), header.encoding);
  auto truncated = [](const PlyElement& element, uint64_t item) {
    return parse_error("invalid ply file: truncated or malformed data in element " + element.name +
                       " (item " + std::to_string(item) + " of " + std::to_string(element.count) +
                       ")");
  };

  // Vertex data as read; per-vertex attributes are attached once the faces are known.
  std::vector<float> vertex_normals, vertex_uvs;
  uint32_t color_components = 0;
  // Faces as read: corners, and per corner the texture coordinate and normal (NaN: none).
  std::vector<uint32_t> corner_counts;
  // Corner vertex indices as 32 bits (half the memory of the values as read); a value that
  // does not fit, which is an error once the vertex count is known, is kept aside (the
  // first one: no later one can be the one reported).
  std::vector<uint32_t> corners;
  std::size_t wide_corner = std::numeric_limits<std::size_t>::max();  // its position
  int64_t wide_corner_value = 0;
  auto add_corner = [&corners, &wide_corner, &wide_corner_value](int64_t value) {
    if (value < 0 || value > int64_t{std::numeric_limits<uint32_t>::max()}) {
      if (wide_corner == std::numeric_limits<std::size_t>::max()) {
        wide_corner = corners.size();
        wide_corner_value = value;
      }
      value = std::numeric_limits<uint32_t>::max();  // never a vertex: see the check below
    }
    corners.push_back(static_cast<uint32_t>(value));
  };
  std::vector<float> corner_uvs, corner_normals;
  std::vector<int64_t> face_materials;
  bool has_corner_uvs = false, has_corner_normals = false, has_materials = false;
  std::vector<float> list_values;  // one list's values, reused

  for (const PlyElement& element : header.elements) {
    const bool is_vertex = element.name == "vertex";
    const bool is_face = element.name == "face";
    std::vector<PlyRole> roles;
    for (const PlyProperty& property : element.properties) roles.push_back(property.role);
    auto has_role = [&roles](PlyRole role) {
      return std::find(roles.begin(), roles.end(), role) != roles.end();
    };
    // Every item takes at least one byte (binary) or two characters (ASCII): bound the
    // reservations by what the file can hold.
    const std::size_t reservable = std::min<uint64_t>(element.count, reader.remaining() / 2 + 1);
    bool with_normals = false, with_uvs = false, with_alpha = false;
    if (is_vertex) {
      if (!has_role(PlyRole::kX) || !has_role(PlyRole::kY) || !has_role(PlyRole::kZ))
        return parse_error("invalid ply file: element vertex has no x, y and z");
      with_normals = has_role(PlyRole::kNormalX);
      with_uvs = has_role(PlyRole::kU);
      if (has_role(PlyRole::kRed)) {
        with_alpha = has_role(PlyRole::kAlpha);
        color_components = with_alpha ? 4 : 3;
        mesh.colors.reserve(color_components * reservable);
      }
      mesh.positions.reserve(3 * reservable);
      if (with_normals) vertex_normals.reserve(3 * reservable);
      if (with_uvs) vertex_uvs.reserve(2 * reservable);
    }
    if (is_face) {
      if (!has_role(PlyRole::kVertexIndices))
        return parse_error("invalid ply file: element face has no vertex_indices");
      has_corner_uvs = has_role(PlyRole::kCornerUvs);
      has_corner_normals = has_role(PlyRole::kCornerNormals);
      has_materials = has_role(PlyRole::kMaterial);
      corner_counts.reserve(reservable);
      corners.reserve(3 * reservable);
    }
    // One item's scalar values by role, and what finishes a vertex or a face: shared by the
    // value-by-value loop and the fixed-layout ones below.
    struct Item {
      float position[3] = {0, 0, 0}, normal[3] = {0, 0, 0}, uv[2] = {0, 0};
      float color[4] = {0, 0, 0, 1};
    };
    auto take_scalar = [&face_materials](const PlyProperty& property, double value, Item& it) {
      switch (property.role) {
        case PlyRole::kX:
        case PlyRole::kY:
        case PlyRole::kZ:
          it.position[static_cast<int>(property.role) - static_cast<int>(PlyRole::kX)] =
              narrow_to_float(value);
          break;
        case PlyRole::kNormalX:
        case PlyRole::kNormalY:
        case PlyRole::kNormalZ:
          it.normal[static_cast<int>(property.role) - static_cast<int>(PlyRole::kNormalX)] =
              narrow_to_float(value);
          break;
        case PlyRole::kU:
        case PlyRole::kV:
          it.uv[static_cast<int>(property.role) - static_cast<int>(PlyRole::kU)] =
              narrow_to_float(value);
          break;
        case PlyRole::kRed:
        case PlyRole::kGreen:
        case PlyRole::kBlue:
        case PlyRole::kAlpha:
          it.color[static_cast<int>(property.role) - static_cast<int>(PlyRole::kRed)] =
              ply_color(property.type, value);
          break;
        case PlyRole::kMaterial:
          face_materials.push_back(static_cast<int64_t>(value));
          break;
        default:
          break;
      }
    };
    auto store_vertex = [&](uint64_t item, const Item& it) {
      for (int axis = 0; axis < 3; ++axis) {
        if (!std::isfinite(it.position[axis])) {
          return parse_error("vertex " + std::to_string(item) + " has a non-finite coordinate");
        }
      }
      // One push_back per value: a three-value insert is an out-of-line call costing more
      // than the rest of the vertex.
      for (float value : it.position) mesh.positions.push_back(value);
      if (color_components != 0) {
        for (uint32_t k = 0; k < color_components; ++k) {
          if (!std::isfinite(it.color[k]))
            return parse_error("vertex " + std::to_string(item) + " has a non-finite colour");
        }
        mesh.colors.insert(mesh.colors.end(), it.color, it.color + color_components);
      }
      if (with_normals) vertex_normals.insert(vertex_normals.end(), it.normal, it.normal + 3);
      if (with_uvs) vertex_uvs.insert(vertex_uvs.end(), it.uv, it.uv + 2);
      return Status::ok();
    };
    auto store_face = [&](uint64_t item, uint32_t corner_count, std::size_t uv_values,
                          std::size_t normal_values) {
      if (corner_count < 3) {
        return parse_error("invalid ply file: face " + std::to_string(item) +
                           " has fewer than 3 corners");
      }
      if (has_corner_uvs && uv_values != 0 && uv_values != 2 * std::size_t{corner_count}) {
        return parse_error("face " + std::to_string(item) + ": texcoord has " +
                           std::to_string(uv_values) + " values for " +
                           std::to_string(corner_count) + " corners");
      }
      if (has_corner_normals && normal_values != 0 &&
          normal_values != 3 * std::size_t{corner_count}) {
        return parse_error("face " + std::to_string(item) + ": corner_normals has " +
                           std::to_string(normal_values) + " values for " +
                           std::to_string(corner_count) + " corners");
      }
      // An empty list: no corner of the face has one.
      const float nan = std::numeric_limits<float>::quiet_NaN();
      if (has_corner_uvs && uv_values == 0)
        corner_uvs.insert(corner_uvs.end(), 2 * corner_count, nan);
      if (has_corner_normals && normal_values == 0)
        corner_normals.insert(corner_normals.end(), 3 * corner_count, nan);
      corner_counts.push_back(corner_count);
      return Status::ok();
    };

    // Binary data in the layouts nearly every file has is read without the value-by-value
    // loop's call, bounds check and dispatch per value (it took most of the time of reading
    // a binary file): an element of scalars only, whose items all have one size, and a face
    // element with no property besides its vertex_indices list. Each stops before an item
    // that does not fit whole or has a bad list length, and the loop below reads that item
    // again and reports it, so that errors are the same on both paths.
    uint64_t item = 0;
    if (reader.is_binary() &&
        std::none_of(element.properties.begin(), element.properties.end(),
                     [](const PlyProperty& property) { return property.is_list; })) {
      std::vector<std::size_t> offsets;
      std::size_t item_size = 0;
      for (const PlyProperty& property : element.properties) {
        offsets.push_back(item_size);
        item_size += ply_type_size(property.type);
      }
      const uint64_t whole =
          item_size == 0 ? 0 : std::min<uint64_t>(element.count, reader.remaining() / item_size);
      const char* at = reader.cursor();
      for (; item < whole; ++item, at += item_size) {
        Item it;
        for (std::size_t k = 0; k < offsets.size(); ++k) {
          const PlyProperty& property = element.properties[k];
          take_scalar(property, reader.decode(property.type, at + offsets[k]), it);
        }
        if (is_vertex) {
          if (Status status = store_vertex(item, it); !status) return status;
        }
      }
      reader.skip(static_cast<std::size_t>(whole * item_size));
    } else if (reader.is_binary() && is_face && element.properties.size() == 1 &&
               element.properties[0].role == PlyRole::kVertexIndices &&
               is_ply_integer(element.properties[0].type)) {
      const PlyType count_type = element.properties[0].count_type;
      const PlyType index_type = element.properties[0].type;
      const std::size_t count_size = ply_type_size(count_type);
      const std::size_t index_size = ply_type_size(index_type);
      const char* at = reader.cursor();
      const char* const start = at;
      std::size_t left = reader.remaining();
      for (; item < element.count; ++item) {
        if (left < count_size) break;
        const int64_t length = reader.decode_integer(count_type, at);
        // As the loop below checks it: each value takes at least a byte.
        if (length < 0 || static_cast<uint64_t>(length) > left - count_size) break;
        const std::size_t corner_count = static_cast<std::size_t>(length);
        if (left - count_size < corner_count * index_size) break;
        at += count_size;
        for (std::size_t i = 0; i < corner_count; ++i, at += index_size)
          add_corner(reader.decode_integer(index_type, at));
        left -= count_size + corner_count * index_size;
        if (Status status = store_face(item, static_cast<uint32_t>(corner_count), 0, 0); !status)
          return status;
      }
      reader.skip(static_cast<std::size_t>(at - start));
    }

    for (; item < element.count; ++item) {
      Item it;
      uint32_t corner_count = 0;
      std::size_t uv_values = 0, normal_values = 0;
      for (const PlyProperty& property : element.properties) {
        double value = 0;
        if (property.is_list) {
          if (!reader.read(property.count_type, value)) return truncated(element, item);
          // Each value takes at least a byte, or two characters.
          if (value < 0 || value > static_cast<double>(reader.remaining())) {
            return parse_error("invalid ply file: element " + element.name + " item " +
                               std::to_string(item) + ": bad list length");
          }
          const std::size_t length = static_cast<std::size_t>(value);
          list_values.clear();
          for (std::size_t i = 0; i < length; ++i) {
            if (!reader.read(property.type, value)) return truncated(element, item);
            switch (property.role) {
              case PlyRole::kVertexIndices:
                add_corner(static_cast<int64_t>(value));
                break;
              case PlyRole::kCornerUvs:
              case PlyRole::kCornerNormals:
                list_values.push_back(narrow_to_float(value));
                break;
              default:
                break;
            }
          }
          if (property.role == PlyRole::kVertexIndices) {
            corner_count = static_cast<uint32_t>(length);
          } else if (property.role == PlyRole::kCornerUvs) {
            uv_values = length;
            corner_uvs.insert(corner_uvs.end(), list_values.begin(), list_values.end());
          } else if (property.role == PlyRole::kCornerNormals) {
            normal_values = length;
            corner_normals.insert(corner_normals.end(), list_values.begin(), list_values.end());
          }
          continue;
        }
        if (!reader.read(property.type, value)) return truncated(element, item);
        take_scalar(property, value, it);
      }
      if (is_vertex) {
        if (Status status = store_vertex(item, it); !status) return status;
      }
      if (is_face) {
        if (Status status = store_face(item, corner_count, uv_values, normal_values); !status)
          return status;
      }
    }
  }

  // Faces: check, then fan-triangulate with their corners' attributes.
  const std::size_t vertices = mesh.vertex_count();
  const bool any_material = has_materials;
  mesh.material_names = header.material_names;
  std::vector<uint32_t> corner_uv_ids, corner_normal_ids;  // per corner as read
  if (has_corner_uvs) {
    ValueTable table(mesh.uvs, 2);
    corner_uv_ids.resize(corners.size());
    for (std::size_t c = 0; c < corners.size(); ++c) {
      const float* tuple = &corner_uvs[2 * c];
      const TupleKind kind = classify_tuple(tuple, 2);
      if (kind == TupleKind::kInvalid)
        return parse_error("face corner " + std::to_string(c) + " has a non-finite texcoord");
      corner_uv_ids[c] = kind == TupleKind::kNone ? kNoAttribute : table.add(tuple);
    }
  }
  if (has_corner_normals) {
    ValueTable table(mesh.normals, 3);
    corner_normal_ids.resize(corners.size());
    for (std::size_t c = 0; c < corners.size(); ++c) {
      const float* tuple = &corner_normals[3 * c];
      const TupleKind kind = classify_tuple(tuple, 3);
      if (kind == TupleKind::kInvalid)
        return parse_error("face corner " + std::to_string(c) + " has a non-finite normal");
      corner_normal_ids[c] = kind == TupleKind::kNone ? kNoAttribute : table.add(tuple);
    }
  }
  // The output arrays at their final size, written through pointers: a push_back per
  // corner was a tenth of the time of reading a binary file.
  const std::size_t triangles = corners.size() - 2 * corner_counts.size();  // each face >= 3
  mesh.triangles.resize(3 * triangles);
  if (has_corner_uvs) mesh.uv_indices.resize(3 * triangles);
  if (has_corner_normals) mesh.normal_indices.resize(3 * triangles);
  if (any_material) mesh.face_materials.resize(triangles);
  uint32_t* triangle_out = mesh.triangles.data();
  uint32_t* uv_out = mesh.uv_indices.data();
  uint32_t* normal_out = mesh.normal_indices.data();
  uint32_t* material_out = mesh.face_materials.data();
  std::size_t first_corner = 0;
  for (std::size_t face = 0; face < corner_counts.size(); ++face) {
    const uint32_t count = corner_counts[face];
    const uint32_t* face_corners = corners.data() + first_corner;
    for (uint32_t i = 0; i < count; ++i) {
      // A value set aside reads as 2^32 - 1 here, which is no vertex: there are fewer.
      if (face_corners[i] >= vertices) {
        const int64_t value =
            first_corner + i == wide_corner ? wide_corner_value : int64_t{face_corners[i]};
        return parse_error("face " + std::to_string(face) + " uses vertex " +
                           std::to_string(value) + " of " + std::to_string(vertices));
      }
    }
    uint32_t material = kNoAttribute;
    if (any_material) {
      const int64_t value = face_materials[face];
      if (value < -1 || value >= static_cast<int64_t>(mesh.material_names.size())) {
        return parse_error("face " + std::to_string(face) + ": pm_material " +
                           std::to_string(value) + " out of range (" +
                           std::to_string(mesh.material_names.size()) + " materials)");
      }
      if (value >= 0) material = static_cast<uint32_t>(value);
    }
    if (count > 3) ++report.polygons_triangulated;
    for (uint32_t i = 1; i + 1 < count; ++i) {
      for (uint32_t k : {uint32_t{0}, i, i + 1}) {
        *triangle_out++ = face_corners[k];
        if (has_corner_uvs) *uv_out++ = corner_uv_ids[first_corner + k];
        if (has_corner_normals) *normal_out++ = corner_normal_ids[first_corner + k];
      }
      if (any_material) *material_out++ = material;
    }
    first_corner += count;
  }
  if (vertices == 0) return Status(ErrorCode::kEmptyMesh, "no vertices or faces");

  mesh.color_components = color_components;
  if (!vertex_normals.empty()) {
    const int64_t bad =
        attach_per_vertex(vertex_normals, 3, mesh.triangles, mesh.normals, mesh.normal_indices);
    if (bad >= 0) return parse_error("vertex " + std::to_string(bad) + " has a non-finite normal");
  }
  if (!vertex_uvs.empty()) {
    const int64_t bad = attach_per_vertex(vertex_uvs, 2, mesh.triangles, mesh.uvs, mesh.uv_indices);
    if (bad >= 0) {
      return parse_error("vertex " + std::to_string(bad) + " has a non-finite texture coordinate");
    }
  }
  return Status::ok();
}

// ---------------------------------------------------------------------------------------------
// OpenMesh reading

std::mutex& openmesh_mutex() {
  static std::mutex mutex;
  return mutex;
}


enum class StlKind { kAscii, kBinary, kInvalid };

StlKind detect_stl(std::string_view bytes) {
  // Binary first: its 80-byte header may well begin with "solid" too.
  if (bytes.size() >= 84) {
    const auto* count_bytes = reinterpret_cast<const unsigned char*>(bytes.data() + 80);
    const uint64_t triangles = uint64_t{count_bytes[0]} | uint64_t{count_bytes[1]} << 8 |
                               uint64_t{count_bytes[2]} << 16 | uint64_t{count_bytes[3]} << 24;
    if (84 + 50 * triangles == bytes.size()) return StlKind::kBinary;
  }
  std::size_t i = 0;
  while (i < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[i]))) ++i;
  if (lower_case(bytes.substr(i, 5)) == "solid") return StlKind::kAscii;
  return StlKind::kInvalid;
}

// Checks that ASCII STL text follows the grammar, one statement per line:
//   solid [name] { facet normal x y z / outer loop / vertex x y z (3 times) / endloop /
//   endfacet } endsolid [name], possibly several solids.
// OpenMesh's ASCII reader does not check: it reads "vertex 1,5 0 0" as (1, 0, 0), accepts
// words for numbers, and silently drops a facet with a NaN or with two vertices.
Status validate_ascii_stl(std::string_view bytes) {
  enum class Expect { kSolid, kFacetOrEndsolid, kOuterLoop, kVertex, kEndloop, kEndfacet };
  Expect expect = Expect::kSolid;
  int vertices_in_loop = 0;
  std::size_t line_number = 0;
  std::size_t pos = 0;
  auto error = [&line_number](const std::string& what) {
    return parse_error("line " + std::to_string(line_number) + ": " + what);
  };
  // Whether tokens[first..] are exactly three finite numbers.
  auto three_numbers = [](const std::vector<std::string_view>& tokens, std::size_t first) {
    if (tokens.size() != first + 3) return false;
    for (std::size_t i = first; i < first + 3; ++i) {
      const char* p = tokens[i].data();
      const char* const end = p + tokens[i].size();
      float value = 0;
      if (detail::parse_float(p, end, value) != detail::NumberResult::kOk || p != end ||
          !std::isfinite(value)) {
        return false;
      }
    }
    return true;
  };
  while (pos < bytes.size()) {
    ++line_number;
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string_view::npos) eol = bytes.size();
    const std::string_view line = bytes.substr(pos, eol - pos);
    pos = eol == bytes.size() ? eol : eol + 1;
    const std::vector<std::string_view> tokens = split_tokens(line);
    if (tokens.empty()) continue;
    const std::string_view keyword = tokens[0];
    switch (expect) {
      case Expect::kSolid:
        // The name is free text.
        if (keyword != "solid") return error("expected solid");
        expect = Expect::kFacetOrEndsolid;
        break;
      case Expect::kFacetOrEndsolid:
        if (keyword == "endsolid") {
          expect = Expect::kSolid;
        } else if (keyword == "facet" && tokens.size() >= 2 && tokens[1] == "normal" &&
                   three_numbers(tokens, 2)) {
          expect = Expect::kOuterLoop;
        } else {
          return error("expected facet normal x y z, or endsolid");
        }
        break;
      case Expect::kOuterLoop:
        if (tokens.size() != 2 || keyword != "outer" || tokens[1] != "loop") {
          return error("expected outer loop");
        }
        expect = Expect::kVertex;
        vertices_in_loop = 0;
        break;
      case Expect::kVertex:
        if (keyword != "vertex") return error("expected vertex x y z");
        if (!three_numbers(tokens, 1)) return error("malformed vertex");
        if (++vertices_in_loop == 3) expect = Expect::kEndloop;
        break;
      case Expect::kEndloop:
        if (tokens.size() != 1 || keyword != "endloop") return error("expected endloop");
        expect = Expect::kEndfacet;
        break;
      case Expect::kEndfacet:
        if (tokens.size() != 1 || keyword != "endfacet") return error("expected endfacet");
        expect = Expect::kFacetOrEndsolid;
        break;
    }
  }
  if (expect != Expect::kSolid) return error("file ends inside a solid");
  return Status::ok();
}

Status read_with_openmesh(std::string_view bytes, MeshFormat format, Mesh& mesh,
                          ReadReport& report) {
  const char* const name = mesh_format_name(format);
  OpenMesh::IO::Options options;
  bool throw_on_stream_failure = true;
  switch (format) {
    case MeshFormat::kStl: {
      // OpenMesh's STL reader merges vertices with equal positions (STL has no indices, so
      // that is the only way to get a connected mesh) and then skips faces that this made
      // degenerate, i.e. triangles with two identical corner positions are dropped.
      const StlKind kind = detect_stl(bytes);
      if (kind == StlKind::kInvalid) return parse_error("not a valid stl file");
      if (kind == StlKind::kBinary) options += OpenMesh::IO::Options::Binary;
      if (kind == StlKind::kAscii) {
        if (Status status = validate_ascii_stl(bytes); !status) return status;
      }
      // The ASCII reader reads lines until the end, which fails the stream at the end.
      throw_on_stream_failure = false;
      break;
    }
    default:
      return Status(ErrorCode::kInternal, "no openmesh reader for this format");
  }

  // The reader sees a copy; std::istringstream cannot wrap memory it does not own.
  std::istringstream in(std::string(bytes), std::ios_base::in | std::ios_base::binary);
  in.imbue(std::locale::classic());
  RawMeshImporter importer(in, bytes.size(), throw_on_stream_failure);
  bool ok = false;
  std::string abort_message;
  try {
    std::lock_guard<std::mutex> lock(openmesh_mutex());
    silence_openmesh_logs();
    ok = OpenMesh::IO::IOManager().read(in, name, importer, options);
  } catch (const AbortRead& abort) {
    abort_message = abort.message;
  } catch (const std::ios_base::failure&) {
    abort_message = "truncated or malformed data";
  } catch (const std::bad_alloc&) {
    return Status(ErrorCode::kResourceLimit,
                  std::string("out of memory reading ") + name + " file");
  } catch (const std::exception& e) {
    abort_message = lower_case(e.what());
  }
  if (!abort_message.empty())
    return parse_error(std::string("invalid ") + name + " file: " + abort_message);
  if (!ok) return parse_error(std::string("not a valid ") + name + " file");

  if (importer.header_counts_known && format != MeshFormat::kStl) {
    if (importer.vertex_count() != importer.header_vertices) {
      return parse_error(std::string("invalid ") + name + " file: header declares " +
                         std::to_string(importer.header_vertices) + " vertices, found " +
                         std::to_string(importer.vertex_count()));
    }
    if (importer.n_faces() != importer.header_faces) {
      return parse_error(std::string("invalid ") + name + " file: header declares " +
                         std::to_string(importer.header_faces) + " faces, found " +
                         std::to_string(importer.n_faces()));
    }
  }
  return build_mesh(importer, mesh, report);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Public API

std::vector<std::string> describe_read_report(const ReadReport& report) {
  std::vector<std::string> lines;
  auto count = [&lines](std::size_t n, const char* one, const char* many) {
    if (n == 0) return;
    lines.push_back(std::to_string(n) + " " + (n == 1 ? one : many));
  };
  count(report.polygons_triangulated, "polygon was split into triangles",
        "polygons were split into triangles");
  count(report.ignored_lines, "line of an unused kind was ignored",
        "lines of unused kinds were ignored");
  count(report.vertex_weights_dropped, "vertex weight w != 1 was not kept",
        "vertex weights w != 1 were not kept");
  count(report.texture_depths_dropped, "texture coordinate w != 0 was not kept",
        "texture coordinate w values != 0 were not kept");
  count(report.vertices_given_default_color, "vertex without a colour was given white",
        "vertices without a colour were given white");
  for (const std::string& property : report.ignored_properties) {
    lines.push_back("not kept: " + property);
  }
  return lines;
}

MeshFormat mesh_format_from_path(std::string_view path) {
  const std::size_t slash = path.find_last_of("/\\");
  const std::string_view file_name =
      slash == std::string_view::npos ? path : path.substr(slash + 1);
  const std::size_t dot = file_name.rfind('.');
  if (dot == std::string_view::npos) return MeshFormat::kUnknown;
  const std::string extension = lower_case(file_name.substr(dot + 1));
  if (extension == "obj") return MeshFormat::kObj;
  if (extension == "ply") return MeshFormat::kPly;
  if (extension == "off") return MeshFormat::kOff;
  if (extension == "stl") return MeshFormat::kStl;
  return MeshFormat::kUnknown;
}

const char* mesh_format_name(MeshFormat format) {
  switch (format) {
    case MeshFormat::kObj:
      return "obj";
    case MeshFormat::kPly:
      return "ply";
    case MeshFormat::kOff:
      return "off";
    case MeshFormat::kStl:
      return "stl";
    case MeshFormat::kUnknown:
      break;
  }
  return "unknown";
}

Status read_mesh_from_memory(std::string_view bytes, MeshFormat format, Mesh& mesh,
                             ReadReport* report) {
  Mesh parsed;
  ReadReport parsed_report;
  Status status;
  switch (format) {
    case MeshFormat::kObj:
      status = detail::read_obj(bytes, parsed, parsed_report);
      break;
    case MeshFormat::kOff:
      status = read_off(bytes, parsed, parsed_report);
      break;
    case MeshFormat::kPly:
      if (bytes.empty()) return Status(ErrorCode::kEmptyMesh, "no vertices or faces");
      status = read_ply(bytes, parsed, parsed_report);
      break;
    case MeshFormat::kStl:
      if (bytes.empty()) return Status(ErrorCode::kEmptyMesh, "no vertices or faces");
      status = read_with_openmesh(bytes, format, parsed, parsed_report);
      break;
    case MeshFormat::kUnknown:
      return Status(ErrorCode::kUnsupportedFormat, "unknown mesh format (use .obj .ply .off .stl)");
  }
  if (!status) return status;
  mesh = std::move(parsed);
  if (report != nullptr) *report = parsed_report;
  return Status::ok();
}

Status read_mesh(const std::string& path, Mesh& mesh, ReadReport* report) {
  const MeshFormat format = mesh_format_from_path(path);
  if (format == MeshFormat::kUnknown) {
    return Status(ErrorCode::kUnsupportedFormat, "unknown mesh format (use .obj .ply .off .stl)");
  }
  auto describe_errno = [](const char* what, int error_number) {
    std::string reason = std::strerror(error_number);
    if (!reason.empty())
      reason[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(reason[0])));
    return Status(ErrorCode::kIoError, std::string(what) + " (" + reason + ")");
  };
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                       &std::fclose);
  if (!file) return describe_errno("cannot open file", errno);
  // The size from the file system is only a hint (pipes and /dev/stdin have none, files may
  // grow): read until end of file, the first read sized to hit it at once.
  std::error_code size_error;
  const uintmax_t size_hint = std::filesystem::file_size(path, size_error);
  // A buffer that is not zero-filled first, as std::string::resize would (a pass over the
  // whole file's worth of memory before fread writes it).
  std::size_t capacity =
      size_error ? (std::size_t{1} << 20) : static_cast<std::size_t>(size_hint) + 1;
  std::unique_ptr<char[]> bytes(new char[capacity]);
  std::size_t size = 0;
  for (;;) {
    const std::size_t got = std::fread(bytes.get() + size, 1, capacity - size, file.get());
    size += got;
    if (size < capacity) break;
    std::unique_ptr<char[]> larger(new char[2 * capacity]);
    std::memcpy(larger.get(), bytes.get(), size);
    bytes = std::move(larger);
    capacity *= 2;
  }
  if (std::ferror(file.get())) return describe_errno("cannot read file", errno);
  return read_mesh_from_memory(std::string_view(bytes.get(), size), format, mesh, report);
}

}  // namespace pm
