// Format detection, file reading and dispatch. OBJ has its own parser (obj_reader.cpp), OFF
// is parsed here, PLY and STL go through OpenMesh's readers.
//
// OpenMesh's readers normally feed a PolyMesh, whose add_face refuses non-manifold faces and
// so silently drops data. Here they feed RawMeshImporter instead, which only records the
// vertices and faces it is given, so what the encoder sees is exactly what the file holds.
//
// OpenMesh's stream readers trust their input more than a library reading user files can:
//  - Counts come from headers and drive loops; a garbage count loops for a very long time.
//    The importer therefore ignores reserve() for allocation, caps the number of elements
//    by the input size, and aborts (by throwing through the reader) on the first face that
//    cannot be right.
//  - A truncated or malformed text body leaves the std::istream failed while the reader
//    keeps going, feeding stale values. For PLY the stream is switched to throw on failure
//    once the header has been read (the reader calls reserve() at that point), and the
//    numbers of vertices and faces received must match the header's.
//  - The PLY header parser loops forever (growing memory) on a header without end_header,
//    and worse (see normalize_ply); the header is checked and rewritten in canonical form.
//  - The STL stream reader reads binary only when told to, and then trusts the triangle
//    count; the type is detected here, and a binary file's size must match its count. Its
//    ASCII reader accepts malformed numbers as garbage coordinates, so ASCII STL is
//    validated first (validate_ascii_stl).
//  - Text numbers are read with iostreams; ours are imbued with the classic locale, but
//    streams OpenMesh makes itself (STL ASCII lines) use the global C++ locale, so a
//    program must not make a locale with a decimal comma global.
// OpenMesh's readers keep state in process-wide singletons, so reads are serialized.
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
#include <utility>
#include <vector>

#include "mesh_readers.h"

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

  // Everything else a reader may hand over (normals, colours, texture coordinates, status,
  // topology) is not part of a pm::Mesh.
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
// OFF

// Reads ASCII OFF: an optional [ST][C][N]OFF keyword line, the counts "vertices faces
// [edges]" (on that line or the next), one vertex per line (x y z, then normals, colours or
// texture coordinates, ignored), one face per line (n i1 .. in, 0-based, then an optional
// colour, ignored). '#' starts a comment anywhere. Whatever follows the faces is ignored.
// Errors name the line, like the OBJ reader's.
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
  if (prefix.substr(0, 2) == "ST") prefix.remove_prefix(2);
  if (!prefix.empty() && prefix[0] == 'C') prefix.remove_prefix(1);
  if (!prefix.empty() && prefix[0] == 'N') prefix.remove_prefix(1);
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

  mesh.positions.clear();
  mesh.triangles.clear();
  report = ReadReport();
  // Counts are untrusted: reserve no more than the rest of the file can hold (the shortest
  // vertex line is "0 0 0\n", the shortest face line "3 0 0 0\n"); loops end with the lines.
  mesh.positions.reserve(3 * std::min(vertices, remaining / 6 + 1));
  mesh.triangles.reserve(3 * std::min(faces, remaining / 8 + 1));
  for (uint64_t v = 0; v < vertices; ++v) {
    if (!next_content_line()) {
      return error("file ends after " + std::to_string(v) + " of " + std::to_string(vertices) +
                   " vertices");
    }
    q = line_begin;
    for (int axis = 0; axis < 3; ++axis) {
      q = detail::skip_blanks(q, line_end);
      float value = 0;
      if (const char* problem = detail::coordinate_problem(detail::parse_float(q, line_end, value)))
        return error(problem);
      if (!std::isfinite(value)) return error("non-finite coordinate");
      mesh.positions.push_back(value);
    }
  }
  std::vector<uint32_t> corners;
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
    if (corners.size() > 3) ++report.polygons_triangulated;
    for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
      mesh.triangles.insert(mesh.triangles.end(), {corners[0], corners[i], corners[i + 1]});
    }
  }
  return Status::ok();
}

// ---------------------------------------------------------------------------------------------
// PLY header normalization

// The scalar types of PLY (both spellings), which OpenMesh's reader knows.
bool is_ply_scalar_type(std::string_view type) {
  for (std::string_view known :
       {"char", "uchar", "short", "ushort", "int", "uint", "float", "double", "int8", "uint8",
        "int16", "uint16", "int32", "uint32", "float32", "float64"}) {
    if (type == known) return true;
  }
  return false;
}

// OpenMesh reads list counts only as uchar/uint8, uint16 or int; map the other integer types
// to the one of the same size (counts are never negative nor beyond 2^31 in a real file).
std::string_view ply_list_count_type(std::string_view type) {
  if (type == "uchar" || type == "uint8" || type == "char" || type == "int8") return "uchar";
  if (type == "ushort" || type == "uint16" || type == "short" || type == "int16") return "uint16";
  if (type == "int" || type == "int32" || type == "uint" || type == "uint32") return "int";
  return {};
}

// Re-emits the PLY header in the canonical form OpenMesh's header parser handles, followed by
// the body unchanged. That parser reads the header as loose tokens: it loops forever (growing
// memory) without end_header, indexes an empty element list when a property comes first,
// prints to std::cerr on unknown types, misplaces binary data when a comment line precedes
// end_header, and takes words inside obj_info lines for keywords. Here the header is read
// line by line and checked; comments, obj_info and unknown lines are dropped.
Status normalize_ply(std::string_view bytes, std::string& normalized) {
  std::string header;
  std::size_t pos = 0;
  bool first_line = true;
  bool saw_format = false;
  bool saw_element = false;
  bool saw_vertex = false;
  bool saw_face = false;
  for (;;) {
    if (pos >= bytes.size()) return parse_error("invalid ply file: header has no end_header");
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string_view::npos) eol = bytes.size();
    const std::string_view line = bytes.substr(pos, eol - pos);
    pos = eol == bytes.size() ? eol : eol + 1;
    std::vector<std::string_view> tokens = split_tokens(line);
    if (first_line) {
      if (tokens.size() != 1 || lower_case(tokens[0]) != "ply")
        return parse_error("not a valid ply file");
      first_line = false;
      header += "ply\n";
      continue;
    }
    if (tokens.empty()) continue;
    const std::string_view keyword = tokens[0];
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      if (saw_format || tokens.size() != 3 ||
          (tokens[1] != "ascii" && tokens[1] != "binary_little_endian" &&
           tokens[1] != "binary_big_endian")) {
        return parse_error("invalid ply file: bad format line");
      }
      saw_format = true;
      header += "format " + std::string(tokens[1]) + " 1.0\n";
    } else if (keyword == "element") {
      uint64_t count = 0;
      if (!saw_format || tokens.size() != 3 || !parse_count(tokens[2], count)) {
        return parse_error("invalid ply file: bad element line");
      }
      // Every element takes at least a byte; the reader holds counts in 32 bits.
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
      saw_element = true;
      header += "element " + std::string(tokens[1]) + " " + std::to_string(count) + "\n";
    } else if (keyword == "property") {
      if (!saw_element) return parse_error("invalid ply file: property outside an element");
      if (tokens.size() == 5 && tokens[1] == "list") {
        const std::string_view count_type = ply_list_count_type(tokens[2]);
        if (count_type.empty() || !is_ply_scalar_type(tokens[3])) {
          return parse_error("invalid ply file: unsupported list property types");
        }
        header += "property list " + std::string(count_type) + " " + std::string(tokens[3]) + " " +
                  std::string(tokens[4]) + "\n";
      } else if (tokens.size() == 3 && is_ply_scalar_type(tokens[1])) {
        header += "property " + std::string(tokens[1]) + " " + std::string(tokens[2]) + "\n";
      } else {
        return parse_error("invalid ply file: bad property line");
      }
    }
    // Any other line is skipped, as OpenMesh does: some exporters write free text (Blender
    // 2.4x: "Created by Blender3D ..."), and a dropped line cannot confuse the reader.
  }
  if (!saw_format) return parse_error("invalid ply file: no format line");
  // OpenMesh finds binary data by seeking 12 bytes ("\nend_header\n") past the end of the
  // last header token, which is why no line of this header ends in blanks.
  header += "end_header\n";
  normalized.clear();
  normalized.reserve(header.size() + bytes.size() - pos);
  normalized += header;
  normalized.append(bytes.substr(pos));
  return Status::ok();
}

// ---------------------------------------------------------------------------------------------
// OpenMesh reading

std::mutex& openmesh_mutex() {
  static std::mutex mutex;
  return mutex;
}

// The library never prints; OpenMesh logs through these streams by default.
void silence_openmesh() {
  omerr().disable();
  omlog().disable();
  omout().disable();
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
  std::string text;  // what OpenMesh reads, when it is not `bytes` as is
  OpenMesh::IO::Options options;
  bool throw_on_stream_failure = true;
  switch (format) {
    case MeshFormat::kPly: {
      Status status = normalize_ply(bytes, text);
      if (!status) return status;
      bytes = text;
      break;
    }
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
    silence_openmesh();
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
  std::size_t chunk = size_error ? (std::size_t{1} << 20) : static_cast<std::size_t>(size_hint) + 1;
  std::string bytes;
  for (;;) {
    const std::size_t old_size = bytes.size();
    bytes.resize(old_size + chunk);
    const std::size_t got = std::fread(bytes.data() + old_size, 1, chunk, file.get());
    bytes.resize(old_size + got);
    if (got < chunk) break;
    chunk = std::max(chunk, std::size_t{1} << 20);
  }
  if (std::ferror(file.get())) return describe_errno("cannot read file", errno);
  return read_mesh_from_memory(bytes, format, mesh, report);
}

}  // namespace pm
