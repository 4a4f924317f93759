// Wavefront OBJ reader: a single pass over the bytes in memory, numbers parsed with
// std::from_chars (locale-independent, correctly rounded to float32, and fast).
//
// Only positions and faces are kept. Polygons become triangle fans; texture coordinates,
// normals, groups and materials are accepted and skipped; other statements (l, p, curves,
// surfaces, ...) are skipped and counted in ReadReport::ignored_lines.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <system_error>
#include <vector>

#include "mesh_readers.h"

namespace pm::detail {
namespace {

bool is_identifier_start(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}
bool is_identifier_char(char c) {
  return is_identifier_start(c) || (c >= '0' && c <= '9');
}

// Bytes that never occur in a text OBJ file: NUL and the other C0 controls except the
// whitespace ones (\t \n \v \f \r), and DEL. Their presence means the file is binary (or
// corrupt), which must be an error rather than a mesh made of whatever happened to look
// like statements.
// Written with bitwise operators, without branches, so that loops over it vectorize.
inline bool is_binary_byte(unsigned char c) {
  return (c < 9) | ((c >= 14) & (c < 32)) | (c == 127);
}

// Returns the offset of the first binary byte, or npos. Scans in blocks with a branch-free
// test the compiler vectorizes; only a block that has a hit is searched byte by byte.
std::size_t find_binary_byte(std::string_view bytes) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  constexpr std::size_t kBlock = 256;
  for (std::size_t start = 0; start < bytes.size(); start += kBlock) {
    const std::size_t stop = std::min(bytes.size(), start + kBlock);
    unsigned char any = 0;
    for (std::size_t i = start; i < stop; ++i)
      any |= static_cast<unsigned char>(is_binary_byte(data[i]));
    if (any == 0) continue;
    for (std::size_t i = start; i < stop; ++i) {
      if (is_binary_byte(data[i])) return i;
    }
  }
  return std::string_view::npos;
}

class ObjParser {
 public:
  ObjParser(std::string_view bytes, Mesh& mesh, ReadReport& report)
      : bytes_(bytes), mesh_(mesh), report_(report) {}

  Status parse() {
    mesh_.positions.clear();
    mesh_.triangles.clear();
    report_ = ReadReport();
    if (std::size_t bad = find_binary_byte(bytes_); bad != std::string_view::npos) {
      return error(line_number_at(bad), bytes_[bad] == '\0'
                                            ? "nul byte in text (binary file?)"
                                            : "control character in text (binary file?)");
    }
    const char* p = bytes_.data();
    const char* const end = p + bytes_.size();
    // A UTF-8 byte order mark, as some Windows tools write, is not part of the first line.
    if (bytes_.substr(0, 3) == "\xEF\xBB\xBF") p += 3;
    while (p != end) {
      ++line_;
      const char* eol =
          static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
      if (eol == nullptr) eol = end;
      Status status = parse_line(p, eol);
      if (!status) return status;
      p = eol == end ? end : eol + 1;
    }
    return finish();
  }

 private:
  Status error(std::size_t line, const std::string& what) const {
    return Status(ErrorCode::kParseError, "line " + std::to_string(line) + ": " + what);
  }
  Status error(const std::string& what) const { return error(line_, what); }

  std::size_t line_number_at(std::size_t offset) const {
    std::size_t line = 1;
    for (std::size_t i = 0; i < offset; ++i) line += bytes_[i] == '\n';
    return line;
  }

  Status parse_line(const char* p, const char* eol) {
    p = skip_blanks(p, eol);
    if (p == eol || *p == '#') return Status::ok();
    const char* keyword_begin = p;
    while (p != eol && !is_blank(*p)) ++p;
    const std::string_view keyword(keyword_begin, static_cast<std::size_t>(p - keyword_begin));

    if (keyword == "v") return parse_vertex(p, eol);
    if (keyword == "f") return parse_face(p, eol);
    // Statements we understand but do not need yet: not worth reporting.
    if (keyword == "vt" || keyword == "vn" || keyword == "o" || keyword == "g" || keyword == "s" ||
        keyword == "usemtl" || keyword == "mtllib") {
      return Status::ok();
    }
    // Any other well-formed statement keyword (l, p, vp, cstype, curv, ...) is skipped and
    // counted; anything else is not OBJ at all.
    bool identifier = is_identifier_start(keyword.front());
    for (char c : keyword) identifier = identifier && is_identifier_char(c);
    if (!identifier) return error("not an obj statement");
    ++report_.ignored_lines;
    return Status::ok();
  }

  // v x y z [w] or v x y z r g b [a]: only x y z are kept.
  Status parse_vertex(const char* p, const char* eol) {
    saw_vertex_or_face_ = true;
    float values[3];
    int count = 0;
    for (;;) {
      p = skip_blanks(p, eol);
      if (p == eol || *p == '#') break;
      float value;
      if (const char* problem = coordinate_problem(parse_float(p, eol, value)))
        return error(problem);
      if (count < 3) {
        if (!std::isfinite(value)) return error("non-finite coordinate");
        values[count] = value;
      }
      ++count;
    }
    if (count < 3 || count > 7) return error("malformed vertex");
    if (vertex_count_ == std::numeric_limits<uint32_t>::max()) {
      return Status(
          ErrorCode::kResourceLimit,
          "line " + std::to_string(line_) + ": more vertices than 32-bit indices can address");
    }
    mesh_.positions.insert(mesh_.positions.end(), values, values + 3);
    ++vertex_count_;
    return Status::ok();
  }

  // f c1 c2 c3 ... where each corner is i, i/t, i//n or i/t/n; negative i counts back from
  // the latest vertex. Positive indices may refer to vertices defined later in the file, so
  // their upper bound is checked once the whole file is read.
  Status parse_face(const char* p, const char* eol) {
    saw_vertex_or_face_ = true;
    corners_.clear();
    for (;;) {
      p = skip_blanks(p, eol);
      if (p == eol || *p == '#') break;
      const char* corner_begin = p;
      int64_t index = 0;
      NumberResult result = parse_int(p, eol, index);
      if (result == NumberResult::kMalformed) return malformed_corner(corner_begin, eol);
      if (result == NumberResult::kOutOfRange) return error("face index out of range");
      // Optional /t, /t/n or //n; their values are not used but must be integers.
      for (int slash = 0; slash < 2 && p != eol && *p == '/'; ++slash) {
        ++p;
        if (p != eol && !is_token_end(p, eol) && *p != '/') {
          int64_t ignored = 0;
          if (parse_int(p, eol, ignored) != NumberResult::kOk)
            return malformed_corner(corner_begin, eol);
        }
      }
      if (!is_token_end(p, eol)) return malformed_corner(corner_begin, eol);

      if (index == 0) return error("face index 0 is invalid (obj indices start at 1)");
      int64_t resolved;
      if (index < 0) {
        resolved = static_cast<int64_t>(vertex_count_) + index;
        if (resolved < 0) return out_of_range(line_, index, vertex_count_);
      } else {
        resolved = index - 1;
        if (index > max_index_) {
          max_index_ = index;
          max_index_line_ = line_;
        }
        if (resolved > std::numeric_limits<uint32_t>::max())
          return out_of_range(line_, index, vertex_count_);
      }
      corners_.push_back(static_cast<uint32_t>(resolved));
    }
    if (corners_.size() < 3) return error("face with fewer than 3 corners");
    if (corners_.size() > 3) ++report_.polygons_triangulated;
    for (std::size_t i = 1; i + 1 < corners_.size(); ++i) {
      mesh_.triangles.push_back(corners_[0]);
      mesh_.triangles.push_back(corners_[i]);
      mesh_.triangles.push_back(corners_[i + 1]);
    }
    return Status::ok();
  }

  Status malformed_corner(const char* corner_begin, const char* eol) const {
    const char* corner_end = corner_begin;
    while (!is_token_end(corner_end, eol)) ++corner_end;
    std::string corner(corner_begin, static_cast<std::size_t>(corner_end - corner_begin));
    if (corner.size() > 40) corner = corner.substr(0, 40) + "...";
    return error("malformed face corner '" + corner + "'");
  }

  Status out_of_range(std::size_t line, int64_t index, std::size_t vertices) const {
    return error(line, "face index " + std::to_string(index) + " out of range (" +
                           std::to_string(vertices) + " vertices)");
  }

  Status finish() {
    if (!saw_vertex_or_face_) return Status(ErrorCode::kEmptyMesh, "no vertices or faces");
    if (max_index_ > static_cast<int64_t>(vertex_count_)) {
      return out_of_range(max_index_line_, max_index_, vertex_count_);
    }
    return Status::ok();
  }

  std::string_view bytes_;
  Mesh& mesh_;
  ReadReport& report_;
  std::size_t line_ = 0;
  std::size_t vertex_count_ = 0;
  bool saw_vertex_or_face_ = false;
  int64_t max_index_ = 0;           // largest positive face index seen
  std::size_t max_index_line_ = 0;  // the line where it first appeared
  std::vector<uint32_t> corners_;   // of the face being parsed, reused between faces
};

}  // namespace

Status read_obj(std::string_view bytes, Mesh& mesh, ReadReport& report) {
  return ObjParser(bytes, mesh, report).parse();
}

}  // namespace pm::detail
