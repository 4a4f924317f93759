// Wavefront OBJ reader (Wavefront OBJ, Appendix B1 of the Advanced Visualizer manual): a
// single pass over the bytes in memory, after a vectorized scan for binary bytes that also
// counts the vertex and face lines (to allocate once); numbers parsed as std::from_chars
// does (locale-independent, correctly rounded to float32), plain decimals, plain indices
// and plain triangles ("f 1 2 3") in fast paths that give the same results (each says how).
//
// Kept: positions, vertex colours (`v x y z r g b [a]`, the extension MeshLab and others
// write), texture coordinates (`vt`), normals (`vn`), face corners in all four forms
// (`v`, `v/vt`, `v//vn`, `v/vt/vn`, indices 1-based or negative = relative), materials
// (`usemtl`) and material library names (`mtllib`; the .mtl files are not read). Polygons
// become triangle fans from their first corner; each triangle takes its corners' texture
// coordinates and normals and the polygon's material.
//
// Defined behaviours for what a mesh cannot hold, each counted in ReadReport:
//  * `v x y z w` (4 values) is a position with a rational weight; w != 1 is dropped.
//    6 values are x y z r g b, 7 are x y z r g b a; 5 or 8+ values are malformed.
//  * if only some vertices have colours, the others get opaque white; if some have 3
//    components and some 4, the 3-component ones get alpha 1 (not counted: it is implied).
//  * `vt u [v [w]]`: v defaults to 0 (as the spec says); a non-zero w is dropped.
//  * `usemtl` without a name ends the current material: the following faces have none.
// Groups, objects and smoothing groups (g, o, s) are accepted and not kept; other statements
// (l, p, curves, surfaces, ...) are skipped and counted in ReadReport::ignored_lines.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <new>
#include <string>
#include <system_error>
#include <unordered_map>
#include <vector>

#include "io/mesh_readers.h"

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

// parse_int for a face index, with a fast path for what nearly every index is: plain
// digits, at most 18 of them (no overflow in int64). Anything else (a sign, more digits, no
// digits) goes to parse_int, so the results and errors are the same.
inline NumberResult parse_index(const char*& p, const char* end, int64_t& value) {
  const char* q = p;
  uint64_t digits = 0;  // wraps around past 19 digits, but is then not used
  while (q != end && static_cast<unsigned char>(*q - '0') < 10) {
    digits = digits * 10 + static_cast<unsigned char>(*q - '0');
    ++q;
  }
  if (q != p && q - p <= 18) {
    value = static_cast<int64_t>(digits);
    p = q;
    return NumberResult::kOk;
  }
  return parse_int(p, end, value);
}

// What one pass over the whole file finds before parsing: the first binary byte (or npos),
// and how many lines start with "v " and "f " (a line break, then the keyword and a
// space), so that the position and triangle arrays are allocated once, at their size,
// instead of growing by doubling (which copied them and touched twice the memory).
struct Prescan {
  std::size_t first_binary = std::string_view::npos;
  std::size_t vertex_lines = 0;
  std::size_t face_lines = 0;
};

// Scans in blocks with branch-free tests the compiler vectorizes; only a block that has a
// binary byte is searched byte by byte. The counts miss a first line and lines indented or
// separated by a tab: they are a reservation, not a result.
Prescan prescan(std::string_view bytes) {
  Prescan found;
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::size_t size = bytes.size();
  constexpr std::size_t kBlock = 256;
  for (std::size_t start = 0; start < size; start += kBlock) {
    const std::size_t stop = std::min(size, start + kBlock);
    unsigned char any = 0;
    for (std::size_t i = start; i < stop; ++i)
      any |= static_cast<unsigned char>(is_binary_byte(data[i]));
    if (any != 0) {
      for (std::size_t i = start; i < stop; ++i) {
        if (is_binary_byte(data[i])) {
          found.first_binary = i;
          return found;
        }
      }
    }
    // "\nv " and "\nf ": the pattern's last two bytes may lie in the next block.
    // Byte-wide counters keep the loop vectorized: a block holds at most 86 matches, since
    // they cannot overlap.
    const std::size_t pattern_stop = std::min(stop, size >= 2 ? size - 2 : 0);
    unsigned char vertices = 0, faces = 0;
    for (std::size_t i = start; i < pattern_stop; ++i) {
      const unsigned char line_then_blank = (data[i] == '\n') & (data[i + 2] == ' ');
      vertices += line_then_blank & (data[i + 1] == 'v');
      faces += line_then_blank & (data[i + 1] == 'f');
    }
    found.vertex_lines += vertices;
    found.face_lines += faces;
  }
  return found;
}

// Indices into one kind of element (vertices, texture coordinates, normals): positive ones
// may refer to elements defined later in the file, so their upper bound is checked once the
// whole file is read; negative ones are resolved against the elements read so far.
struct IndexSpace {
  const char* index_name;    // "face index"
  const char* element_name;  // "vertices"
  std::size_t count = 0;     // elements read so far
  int64_t max_index = 0;     // largest positive index seen
  std::size_t max_index_line = 0;
};

// A face corner while its face is parsed: resolved 0-based indices, kNoAttribute for none.
struct Corner {
  uint32_t vertex;
  uint32_t uv;
  uint32_t normal;
};

class ObjParser {
 public:
  ObjParser(std::string_view bytes, Mesh& mesh, ReadReport& report)
      : bytes_(bytes), mesh_(mesh), report_(report) {}

  Status parse() {
    mesh_ = Mesh();
    report_ = ReadReport();
    const Prescan found = prescan(bytes_);
    if (std::size_t bad = found.first_binary; bad != std::string_view::npos) {
      return error(line_number_at(bad), bytes_[bad] == '\0'
                                            ? "nul byte in text (binary file?)"
                                            : "control character in text (binary file?)");
    }
    // +1 for a first line, which no line break precedes. A vertex or face line that parses
    // takes at least 8 bytes ("v 1 2 3\n"): the reservation is capped by that, so a file of
    // bare "v " lines (which fails on its first) cannot make it reserve more than 1.5 times
    // its size per array.
    // Refused memory is no error here: the arrays then grow as the lines come, as they did
    // before there was a count.
    const std::size_t most_lines = bytes_.size() / 8 + 1;
    try {
      mesh_.positions.reserve(3 * std::min(found.vertex_lines + 1, most_lines));
      mesh_.triangles.reserve(3 * std::min(found.face_lines + 1, most_lines));
      face_capacity_ = mesh_.triangles.capacity();
    } catch (const std::bad_alloc&) {
      mesh_.positions.shrink_to_fit();
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
  Status too_many(const char* what) const {
    return Status(ErrorCode::kResourceLimit, "line " + std::to_string(line_) + ": more " + what +
                                                 " than 32-bit indices can address");
  }

  std::size_t line_number_at(std::size_t offset) const {
    std::size_t line = 1;
    for (std::size_t i = 0; i < offset; ++i) line += bytes_[i] == '\n';
    return line;
  }

  Status parse_line(const char* p, const char* eol) {
    p = skip_blanks(p, eol);
    if (p == eol || *p == '#') return Status::ok();
    // Most lines are "v " or "f ": dispatched before the keyword is measured.
    if (eol - p >= 2 && is_blank(p[1])) {
      if (*p == 'v') return parse_vertex(p + 1, eol);
      if (*p == 'f') return parse_face(p + 1, eol);
    }
    const char* keyword_begin = p;
    while (p != eol && !is_blank(*p)) ++p;
    const std::string_view keyword(keyword_begin, static_cast<std::size_t>(p - keyword_begin));

    if (keyword == "v") return parse_vertex(p, eol);
    if (keyword == "f") return parse_face(p, eol);
    if (keyword == "vt") return parse_texture_coordinate(p, eol);
    if (keyword == "vn") return parse_normal(p, eol);
    if (keyword == "usemtl") return parse_usemtl(p, eol);
    if (keyword == "mtllib") return parse_mtllib(p, eol);
    // Names of groups and objects, smoothing groups: structure a triangle mesh does not have.
    if (keyword == "o" || keyword == "g" || keyword == "s") return Status::ok();
    // Any other well-formed statement keyword (l, p, vp, cstype, curv, ...) is skipped and
    // counted; anything else is not OBJ at all.
    bool identifier = is_identifier_start(keyword.front());
    for (char c : keyword) identifier = identifier && is_identifier_char(c);
    if (!identifier) return error("not an obj statement");
    ++report_.ignored_lines;
    return Status::ok();
  }

  // Reads up to `capacity` numbers to the end of the line (or a comment) into `values`;
  // `count` is how many there were, possibly more than `capacity` (the rest are parsed and
  // dropped, so that the caller can name the line malformed).
  Status parse_numbers(const char* p, const char* eol, float* values, int capacity, int& count,
                       const char* malformed) {
    count = 0;
    for (;;) {
      p = skip_blanks(p, eol);
      if (p == eol || *p == '#') return Status::ok();
      float value;
      const NumberResult result = parse_float(p, eol, value);
      if (result == NumberResult::kMalformed) return error(malformed);
      if (result == NumberResult::kOutOfRange) return error("value out of float range");
      if (count < capacity) values[count] = value;
      ++count;
    }
  }

  // v x y z, v x y z w, v x y z r g b, v x y z r g b a.
  Status parse_vertex(const char* p, const char* eol) {
    saw_vertex_or_face_ = true;
    float values[7];
    int count = 0;
    for (;;) {
      p = skip_blanks(p, eol);
      if (p == eol || *p == '#') break;
      float value;
      if (const char* problem = coordinate_problem(parse_float(p, eol, value)))
        return error(problem);
      if (count < 7) values[count] = value;
      ++count;
    }
    if (count < 3 || count == 5 || count > 7) return error("malformed vertex");
    for (int axis = 0; axis < 3; ++axis) {
      if (!std::isfinite(values[axis])) return error("non-finite coordinate");
    }
    if (vertices_.count == std::numeric_limits<uint32_t>::max()) return too_many("vertices");
    if (count == 4 && values[3] != 1.0f) ++report_.vertex_weights_dropped;
    const int color_components = count >= 6 ? count - 3 : 0;
    for (int c = 0; c < color_components; ++c) {
      if (!std::isfinite(values[3 + c])) return error("non-finite colour");
    }
    add_vertex_color(color_components == 0 ? nullptr : values + 3, color_components);
    // One push_back per value: a three-value insert is an out-of-line call costing as much
    // as parsing a number.
    for (int axis = 0; axis < 3; ++axis) mesh_.positions.push_back(values[axis]);
    ++vertices_.count;
    return Status::ok();
  }

  // Appends the colour of the vertex being added (`color` null when it has none), giving
  // the vertices without one opaque white once any vertex has one.
  void add_vertex_color(const float* color, int components) {
    std::vector<float>& colors = mesh_.colors;
    uint32_t& mesh_components = mesh_.color_components;
    if (color == nullptr) {
      if (mesh_components == 0) return;
      colors.insert(colors.end(), mesh_components, 1.0f);
      ++report_.vertices_given_default_color;
      return;
    }
    if (mesh_components == 0) {
      // The first vertex with a colour: every vertex before it had none.
      mesh_components = static_cast<uint32_t>(components);
      colors.assign(vertices_.count * mesh_components, 1.0f);
      report_.vertices_given_default_color += vertices_.count;
    } else if (mesh_components == 3 && components == 4) {
      // Widen to r g b a: the colours so far are opaque.
      std::vector<float> widened;
      widened.reserve(colors.size() / 3 * 4 + 4);
      for (std::size_t i = 0; i < colors.size(); i += 3) {
        widened.insert(widened.end(), {colors[i], colors[i + 1], colors[i + 2], 1.0f});
      }
      colors.swap(widened);
      mesh_components = 4;
    }
    colors.insert(colors.end(), color, color + components);
    if (mesh_components == 4 && components == 3) colors.push_back(1.0f);
  }

  // vt u [v [w]]
  Status parse_texture_coordinate(const char* p, const char* eol) {
    float values[3] = {0.0f, 0.0f, 0.0f};
    int count = 0;
    if (Status status = parse_numbers(p, eol, values, 3, count, "malformed texture coordinate");
        !status) {
      return status;
    }
    if (count < 1 || count > 3) return error("malformed texture coordinate");
    if (!std::isfinite(values[0]) || !std::isfinite(values[1]))
      return error("non-finite texture coordinate");
    if (values[2] != 0.0f) ++report_.texture_depths_dropped;
    if (uvs_.count == kNoAttribute) return too_many("texture coordinates");
    mesh_.uvs.insert(mesh_.uvs.end(), values, values + 2);
    ++uvs_.count;
    return Status::ok();
  }

  // vn x y z
  Status parse_normal(const char* p, const char* eol) {
    float values[3];
    int count = 0;
    if (Status status = parse_numbers(p, eol, values, 3, count, "malformed normal"); !status)
      return status;
    if (count != 3) return error("malformed normal");
    for (float value : values) {
      if (!std::isfinite(value)) return error("non-finite normal");
    }
    if (normals_.count == kNoAttribute) return too_many("normals");
    mesh_.normals.insert(mesh_.normals.end(), values, values + 3);
    ++normals_.count;
    return Status::ok();
  }

  // usemtl name: the rest of the line (names may hold blanks), without a trailing comment
  // (a '#' after a blank) and trailing blanks. No name: the following faces have none.
  Status parse_usemtl(const char* p, const char* eol) {
    p = skip_blanks(p, eol);
    const char* name_end = p;
    for (const char* q = p; q != eol; ++q) {
      if (*q == '#' && (q == p || is_blank(q[-1]))) break;
      if (!is_blank(*q)) name_end = q + 1;
    }
    const std::string_view name(p, static_cast<std::size_t>(name_end - p));
    if (name.empty()) {
      current_material_ = kNoAttribute;
      return Status::ok();
    }
    if (!materials_started_) {
      // From the first material on, every face has an entry; those before have none.
      materials_started_ = true;
      reserve_like_triangles(mesh_.face_materials, 3);
      mesh_.face_materials.assign(mesh_.face_count(), kNoAttribute);
    }
    if (current_material_ != kNoAttribute && mesh_.material_names[current_material_] == name)
      return Status::ok();
    auto [it, inserted] =
        material_ids_.try_emplace(std::string(name), static_cast<uint32_t>(material_ids_.size()));
    if (inserted) mesh_.material_names.emplace_back(name);
    current_material_ = it->second;
    return Status::ok();
  }

  // mtllib file1 file2 ...: the names, as written (the files are not read).
  Status parse_mtllib(const char* p, const char* eol) {
    for (;;) {
      p = skip_blanks(p, eol);
      if (p == eol || *p == '#') return Status::ok();
      const char* name_begin = p;
      while (p != eol && !is_blank(*p)) ++p;
      mesh_.material_libraries.emplace_back(name_begin, static_cast<std::size_t>(p - name_begin));
    }
  }

  // Resolves one index of a face corner into `space`: 0-based, or false for an index that
  // is out of range (resolve_error says why). Inline and without a Status: it runs for
  // every corner.
  bool resolve(int64_t index, IndexSpace& space, uint32_t& resolved) {
    if (index > 0) {
      // kNoAttribute (2^32 - 1) is no index: 0-based indices stop one below.
      if (index > int64_t{kNoAttribute}) return false;
      if (index > space.max_index) {
        space.max_index = index;
        space.max_index_line = line_;
      }
      resolved = static_cast<uint32_t>(index - 1);
      return true;
    }
    const int64_t zero_based = static_cast<int64_t>(space.count) + index;
    if (index == 0 || zero_based < 0) return false;
    resolved = static_cast<uint32_t>(zero_based);
    return true;
  }

  Status resolve_error(int64_t index, const IndexSpace& space) const {
    if (index == 0) {
      return error(std::string(space.index_name) + " 0 is invalid (obj indices start at 1)");
    }
    return out_of_range(line_, index, space);
  }

  // The fast path of parse_face, for what most faces are: "f a b c", three plain positive
  // vertex indices (at most 10 digits, no sign, no slash) and nothing else but blanks and a
  // comment. Returns false, having changed nothing, for any other line, which parse_face
  // then reads in full; what it does for a line it takes is what parse_face does.
  bool parse_plain_triangle(const char* p, const char* eol) {
    uint32_t corner[3];
    for (uint32_t& vertex : corner) {
      p = skip_blanks(p, eol);
      const char* const digits_begin = p;
      uint64_t index = 0;
      while (p != eol && static_cast<unsigned char>(*p - '0') < 10 && p - digits_begin < 11)
        index = index * 10 + static_cast<unsigned char>(*p++ - '0');
      // kNoAttribute (2^32 - 1) is the largest index resolve() takes.
      if (p == digits_begin || index == 0 || index > kNoAttribute || !is_token_end(p, eol))
        return false;
      vertex = static_cast<uint32_t>(index - 1);
    }
    p = skip_blanks(p, eol);
    if (p != eol && *p != '#') return false;
    for (uint32_t vertex : corner) {
      if (int64_t{vertex} + 1 > vertices_.max_index) {
        vertices_.max_index = int64_t{vertex} + 1;
        vertices_.max_index_line = line_;
      }
    }
    for (uint32_t vertex : corner) {
      mesh_.triangles.push_back(vertex);
      if (uvs_started_) mesh_.uv_indices.push_back(kNoAttribute);
      if (normals_started_) mesh_.normal_indices.push_back(kNoAttribute);
    }
    if (materials_started_) mesh_.face_materials.push_back(current_material_);
    return true;
  }

  // f c1 c2 c3 ... where each corner is v, v/t, v//n or v/t/n (an empty t or n, as in
  // "v/" or "v/t/", is none).
  Status parse_face(const char* p, const char* eol) {
    saw_vertex_or_face_ = true;
    if (parse_plain_triangle(p, eol)) return Status::ok();
    corners_.clear();
    bool face_has_uv = false;
    bool face_has_normal = false;
    for (;;) {
      p = skip_blanks(p, eol);
      if (p == eol || *p == '#') break;
      const char* corner_begin = p;
      int64_t index = 0;
      NumberResult result = parse_index(p, eol, index);
      if (result == NumberResult::kMalformed) return malformed_corner(corner_begin, eol);
      if (result == NumberResult::kOutOfRange) return error("face index out of range");
      int64_t attribute_index[2] = {0, 0};  // t, n; 0 when absent
      for (int slash = 0; slash < 2 && p != eol && *p == '/'; ++slash) {
        ++p;
        if (p != eol && !is_token_end(p, eol) && *p != '/') {
          result = parse_index(p, eol, attribute_index[slash]);
          if (result == NumberResult::kMalformed) return malformed_corner(corner_begin, eol);
          if (result == NumberResult::kOutOfRange) {
            return error(std::string(slash == 0 ? uvs_.index_name : normals_.index_name) +
                         " out of range");
          }
          // An explicit 0 is an index, and invalid: not the same as an empty field.
          if (attribute_index[slash] == 0) {
            return error(std::string(slash == 0 ? uvs_.index_name : normals_.index_name) +
                         " 0 is invalid (obj indices start at 1)");
          }
        }
      }
      if (!is_token_end(p, eol)) return malformed_corner(corner_begin, eol);

      Corner corner{0, kNoAttribute, kNoAttribute};
      if (!resolve(index, vertices_, corner.vertex)) return resolve_error(index, vertices_);
      if (attribute_index[0] != 0) {
        if (!resolve(attribute_index[0], uvs_, corner.uv))
          return resolve_error(attribute_index[0], uvs_);
        face_has_uv = true;
      }
      if (attribute_index[1] != 0) {
        if (!resolve(attribute_index[1], normals_, corner.normal))
          return resolve_error(attribute_index[1], normals_);
        face_has_normal = true;
      }
      corners_.push_back(corner);
    }
    if (corners_.size() < 3) return error("face with fewer than 3 corners");
    if (corners_.size() > 3) ++report_.polygons_triangulated;

    // The first face with texture coordinates (normals) starts the per-corner array; the
    // corners before it have none.
    if (face_has_uv && !uvs_started_) {
      uvs_started_ = true;
      reserve_like_triangles(mesh_.uv_indices);
      mesh_.uv_indices.assign(mesh_.triangles.size(), kNoAttribute);
    }
    if (face_has_normal && !normals_started_) {
      normals_started_ = true;
      reserve_like_triangles(mesh_.normal_indices);
      mesh_.normal_indices.assign(mesh_.triangles.size(), kNoAttribute);
    }
    // A fan from the first corner: (c0 c1 c2), (c0 c2 c3), ...
    for (std::size_t i = 1; i + 1 < corners_.size(); ++i) {
      const Corner* fan[3] = {&corners_[0], &corners_[i], &corners_[i + 1]};
      for (const Corner* corner : fan) mesh_.triangles.push_back(corner->vertex);
      if (uvs_started_) {
        for (const Corner* corner : fan) mesh_.uv_indices.push_back(corner->uv);
      }
      if (normals_started_) {
        for (const Corner* corner : fan) mesh_.normal_indices.push_back(corner->normal);
      }
      if (materials_started_) mesh_.face_materials.push_back(current_material_);
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

  Status out_of_range(std::size_t line, int64_t index, const IndexSpace& space) const {
    return error(line, std::string(space.index_name) + " " + std::to_string(index) +
                           " out of range (" + std::to_string(space.count) + " " +
                           space.element_name + ")");
  }

  Status finish() {
    if (!saw_vertex_or_face_) return Status(ErrorCode::kEmptyMesh, "no vertices or faces");
    // Forward references that never came: report the earliest line among the three kinds.
    const IndexSpace* worst = nullptr;
    for (const IndexSpace* space : {&vertices_, &uvs_, &normals_}) {
      if (space->max_index > static_cast<int64_t>(space->count) &&
          (worst == nullptr || space->max_index_line < worst->max_index_line)) {
        worst = space;
      }
    }
    if (worst != nullptr) return out_of_range(worst->max_index_line, worst->max_index, *worst);
    // The attribute tables grew by doubling (the prescan counts no "vt" or "vn" lines):
    // their slack would stay allocated while the mesh is simplified, where memory peaks.
    mesh_.uvs.shrink_to_fit();
    mesh_.normals.shrink_to_fit();
    return Status::ok();
  }

  // A per-corner (or, with per_face 3, per-face) array started late takes the room the
  // prescan reserved for the triangles, rather than doubling (and keeping up to half of it
  // unused while the mesh is simplified). Refused memory is no error, as in parse().
  void reserve_like_triangles(std::vector<uint32_t>& array, std::size_t per_face = 1) {
    try {
      array.reserve(face_capacity_ / per_face);
    } catch (const std::bad_alloc&) {
    }
  }

  std::string_view bytes_;
  Mesh& mesh_;
  ReadReport& report_;
  std::size_t line_ = 0;
  bool saw_vertex_or_face_ = false;
  IndexSpace vertices_{"face index", "vertices"};
  IndexSpace uvs_{"texture coordinate index", "texture coordinates"};
  IndexSpace normals_{"normal index", "normals"};
  std::size_t face_capacity_ = 0;  // mesh_.triangles' reservation from the prescan
  bool uvs_started_ = false;      // some face corner had a texture coordinate
  bool normals_started_ = false;  // some face corner had a normal
  bool materials_started_ = false;
  uint32_t current_material_ = kNoAttribute;
  std::unordered_map<std::string, uint32_t> material_ids_;  // name -> index in material_names
  std::vector<Corner> corners_;  // of the face being parsed, reused between faces
};

}  // namespace

Status read_obj(std::string_view bytes, Mesh& mesh, ReadReport& report) {
  return ObjParser(bytes, mesh, report).parse();
}

}  // namespace pm::detail
