// Mesh writers: OBJ and OFF text, PLY binary little-endian, STL binary, each with every
// attribute the format can hold (README.md, "Input and output formats"):
//  * OBJ (Wavefront OBJ, Appendix B1): `mtllib`, `v x y z [r g b [a]]`, `vt u v`, `vn x y z`,
//    then the faces in their order, `usemtl` wherever the material differs from the previous
//    face's, corners in the shortest form (a, a/t, a//n, a/t/n). The value tables are
//    written whole, so reading the file back gives the same tables and indices.
//  * PLY (Turk 1994): colours as uchar when every value is exactly k/255 (what the reader
//    makes of a uchar), else float; normals and texture coordinates per vertex (nx ny nz,
//    s t) when each vertex has a single one, else per corner in face lists: MeshLab's
//    `texcoord` (u v per corner) and our `corner_normals` (x y z per corner), with NaN for a
//    corner without one and an empty list for a face without any. Materials, which PLY has no
//    convention for, are `comment pm_material NAME` lines (in table order) and a face
//    property `int pm_material` (-1: none); material libraries are `comment pm_mtllib NAME`.
//  * OFF (Geomview): [ST][C][N]OFF with normals, colours and texture coordinates per vertex;
//    a vertex whose corners have different ones (a UV seam, a crease) is written once per
//    combination, so the values survive but the copies are separate vertices. OFF has no
//    materials: they are not written.
//  * STL: no attributes; the facet normal is derived from the corners.
//  * glTF (.glb binary, .gltf with its buffer inline): one level, gltf_writer.cpp.
//
// Everything is appended to one std::string reserved up front (write_mesh_to_memory), or to a
// buffer of about a megabyte given to the caller's sink each time it fills
// (write_mesh_to_sink: the same bytes, never the whole text in memory); floats are printed with
// std::to_chars (shortest text that reads back to the same float32 bits, locale-independent),
// and binary values are stored byte by byte in little-endian order whatever the host's.

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "pm/gltf.h"
#include "pm/mesh_io.h"
#include "core/no_throw.h"

namespace pm {
namespace {

// A piece given to a sink (write_mesh_to_sink): a megabyte, so that a large mesh's text is
// never whole in memory (pmdec writing the 950,272-face textured mesh at full detail as OBJ
// held its 111 MB of text beside the mesh).
constexpr std::size_t kSinkPiece = std::size_t{1} << 20;

// What a sink's failure unwinds with, up to write_mesh_to_sink(): the writers' loops stop at
// once, with nothing of theirs to undo (they hold no state outside their builder).
struct SinkFailed {
  Status status;
};

// Appends characters at a raw cursor: no per-call size bookkeeping in the hot loops. The
// caller guarantees capacity with ensure(), which makes room for the next write. With a sink,
// `out` is a buffer of about kSinkPiece whose bytes go to the sink when ensure() finds it
// full, and at finish().
class TextBuilder {
 public:
  explicit TextBuilder(std::string& out, const MeshByteSink* sink = nullptr)
      : out_(out), sink_(sink) {}

  void ensure(std::size_t bytes) {
    if (static_cast<std::size_t>(end_ - cursor_) >= bytes) return;
    if (sink_ != nullptr) {
      flush();
      if (static_cast<std::size_t>(end_ - cursor_) >= bytes) return;
    }
    const std::size_t used = size();
    const std::size_t grown = sink_ != nullptr ? std::max(kSinkPiece, used + bytes)
                                               : std::max(out_.size() * 2, used + bytes + 4096);
    out_.resize(grown);
    cursor_ = out_.data() + used;
    end_ = out_.data() + out_.size();
  }
  // `expected`: about the whole output's size (the buffer's, with a sink: at most a piece).
  void begin(std::size_t expected) {
    out_.clear();
    out_.resize(sink_ != nullptr ? std::min(expected, kSinkPiece) : expected);
    cursor_ = out_.data();
    end_ = cursor_ + out_.size();
  }
  void finish() {
    if (sink_ != nullptr) {
      flush();
    } else {
      out_.resize(size());
    }
  }

  void put(char c) { *cursor_++ = c; }
  void put(std::string_view text) {
    std::memcpy(cursor_, text.data(), text.size());
    cursor_ += text.size();
  }
  void put(float value) { cursor_ = std::to_chars(cursor_, end_, value).ptr; }
  void put(uint64_t value) { cursor_ = std::to_chars(cursor_, end_, value).ptr; }
  // "x y z\n" and "a b c\n" (indices plus first_index), the lines OBJ and OFF share.
  void put_xyz_line(const float* p) {
    put(p[0]);
    put(' ');
    put(p[1]);
    put(' ');
    put(p[2]);
    put('\n');
  }
  void put_index_line(const uint32_t* t, uint64_t first_index) {
    put(t[0] + first_index);
    put(' ');
    put(t[1] + first_index);
    put(' ');
    put(t[2] + first_index);
    put('\n');
  }

  void put_u8(uint8_t value) { *cursor_++ = static_cast<char>(value); }
  void put_u16(uint16_t value) {
    put_u8(static_cast<uint8_t>(value));
    put_u8(static_cast<uint8_t>(value >> 8));
  }
  void put_u32(uint32_t value) {
    for (int shift = 0; shift < 32; shift += 8) put_u8(static_cast<uint8_t>(value >> shift));
  }
  void put_f32(float value) {
    uint32_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    put_u32(bits);
  }

 private:
  std::size_t size() const { return static_cast<std::size_t>(cursor_ - out_.data()); }
  // The bytes so far to the sink (none when there are none); a failure unwinds.
  void flush() {
    if (size() == 0) return;
    Status status;
    try {
      status = (*sink_)(std::string_view(out_.data(), size()));
    } catch (const std::bad_alloc&) {
      throw;  // no_throw()'s: out of memory
    } catch (...) {
      status = Status(ErrorCode::kInternal, "the output's sink threw an exception");
    }
    cursor_ = out_.data();
    if (!status) throw SinkFailed{std::move(status)};
  }

  std::string& out_;
  const MeshByteSink* sink_;
  char* cursor_ = nullptr;
  char* end_ = nullptr;
};

// Longest outputs: a float is at most 15 characters ("-1.17549435e-38"), a uint32 10.
constexpr std::size_t kMaxFloatChars = 16;
constexpr std::size_t kMaxIndexChars = 10;
constexpr std::size_t kMaxVertexLine = 2 + 3 * (kMaxFloatChars + 1);  // "v " + "x y z\n"
constexpr std::size_t kMaxFaceLine = 2 + 3 * (kMaxIndexChars + 1);    // "f " + "a b c\n"

Status invalid(std::string message) {
  return Status(ErrorCode::kInvalidArgument, std::move(message));
}

Status validate(const Mesh& mesh) {
  if (mesh.positions.size() % 3 != 0 || mesh.triangles.size() % 3 != 0) {
    return invalid("mesh arrays are not a multiple of 3 long");
  }
  const std::size_t vertices = mesh.vertex_count();
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!std::isfinite(mesh.positions[i])) {
      return invalid("vertex " + std::to_string(i / 3) + " has a non-finite coordinate");
    }
  }
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (mesh.triangles[i] >= vertices) {
      return invalid("face " + std::to_string(i / 3) + " uses vertex " +
                     std::to_string(mesh.triangles[i]) + " of " + std::to_string(vertices));
    }
  }
  if (Status valid = validate_attributes(mesh); !valid) return valid;
  // Readers refuse non-finite attribute values (and NaN means "none" in PLY and OFF lists).
  const std::pair<const std::vector<float>*, const char*> tables[] = {
      {&mesh.colors, "colour"}, {&mesh.uvs, "texture coordinate"}, {&mesh.normals, "normal"}};
  for (const auto& [values, name] : tables) {
    for (float value : *values) {
      if (!std::isfinite(value)) return invalid(std::string("a ") + name + " is not finite");
    }
  }
  return Status::ok();
}

// Whether a material or library name reads back as itself: not empty, no control
// characters but blanks (readers split lines at '\n' and trim blanks at both ends), blanks
// only inside and only if `allow_blanks` (OBJ mtllib splits at them), no '#' where a reader
// would see a comment.
bool is_writable_name(const std::string& name, bool allow_blanks) {
  auto is_blank = [](char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
  };
  if (name.empty() || name.front() == '#' || is_blank(name.front()) || is_blank(name.back()))
    return false;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(name[i]);
    if (is_blank(name[i])) {
      if (!allow_blanks) return false;
    } else if (c < 32 || c == 127) {
      return false;
    }
    if (c == '#' && is_blank(name[i - 1])) return false;
  }
  return true;
}

Status check_names(const Mesh& mesh) {
  for (const std::string& name : mesh.material_names) {
    if (!is_writable_name(name, true))
      return invalid("material name '" + name + "' cannot be written");
  }
  for (const std::string& name : mesh.material_libraries) {
    if (!is_writable_name(name, false))
      return invalid("material library name '" + name + "' cannot be written");
  }
  return Status::ok();
}

bool same_bits(const float* a, const float* b, int count) {
  return std::memcmp(a, b, sizeof(float) * static_cast<std::size_t>(count)) == 0;
}

// For a per-corner attribute (indices into a table of `dims` floats): the table entry of
// each vertex when every corner at the vertex has the same value, bit for bit (vertices no
// corner uses get none). Returns false when some vertex has two values (a seam), or a value
// at some corners and none at others.
bool per_vertex_entries(const Mesh& mesh, const std::vector<uint32_t>& indices,
                        const std::vector<float>& table, int dims, std::vector<uint32_t>& entries) {
  entries.assign(mesh.vertex_count(), kNoAttribute);
  std::vector<bool> seen(mesh.vertex_count(), false);
  for (std::size_t c = 0; c < mesh.triangles.size(); ++c) {
    const uint32_t v = mesh.triangles[c];
    const uint32_t entry = indices[c];
    if (!seen[v]) {
      seen[v] = true;
      entries[v] = entry;
      continue;
    }
    const uint32_t kept = entries[v];
    if (kept == entry) continue;
    if (kept == kNoAttribute || entry == kNoAttribute) return false;
    if (!same_bits(&table[std::size_t{kept} * dims], &table[std::size_t{entry} * dims], dims))
      return false;
  }
  return true;
}

// 8-bit colours are stored as k / 255 by the PLY and OFF readers; this is that value.
float color_from_byte(int k) {
  return static_cast<float>(k) / 255.0f;
}

// Whether every colour is some k / 255 exactly, so that writing bytes loses nothing.
bool colors_are_bytes(const std::vector<float>& colors) {
  for (float value : colors) {
    if (!(value >= 0.0f && value <= 1.0f)) return false;
    const int k = static_cast<int>(std::lround(value * 255.0f));
    const float back = color_from_byte(k);
    if (!same_bits(&back, &value, 1)) return false;
  }
  return true;
}

uint8_t color_byte(float value) {
  return static_cast<uint8_t>(std::lround(value * 255.0f));
}

// ---------------------------------------------------------------------------------------
// OBJ

// Longest lines: "v " + 7 floats, "f " + 3 corners of three indices.
constexpr std::size_t kMaxObjVertexLine = 2 + 7 * (kMaxFloatChars + 1);
constexpr std::size_t kMaxObjFaceLine = 2 + 3 * (3 * (kMaxIndexChars + 1) + 1);

// Decimal digits of n (1 for 0).
std::size_t decimal_digits(uint64_t n) {
  std::size_t digits = 1;
  for (; n >= 10; n /= 10) ++digits;
  return digits;
}

// The size the OBJ text is allocated at. Exceeding it makes the buffer grow, which copies
// everything written so far into a buffer twice as large (zero-filled first, as std::string
// does): that was a third of the time of writing a 4.4M-face mesh whose estimate was 8%
// short. Face lines have an exact bound, from the digits of the largest index of each kind;
// a number of a value line is counted as 12 characters and its separator, which the
// coordinates of most meshes stay under ("-0.012345678"), so that the estimate is rarely
// short. Values of few digits make it long ("v 1 2 3" is 8 bytes of the 41 counted), but
// face lines, twice as many, are counted right.
std::size_t obj_size_estimate(const Mesh& mesh) {
  constexpr std::size_t kValue = 13;
  std::size_t corner = 1 + decimal_digits(mesh.vertex_count());  // " 123"
  if (mesh.has_uvs()) corner += 1 + decimal_digits(mesh.uv_count());
  if (mesh.has_normals()) corner += 2 + decimal_digits(mesh.normal_count());
  return mesh.vertex_count() * (2 + (3 + mesh.color_components) * kValue) +
         mesh.uv_count() * (3 + 2 * kValue) + mesh.normal_count() * (3 + 3 * kValue) +
         mesh.face_count() * (2 + 3 * corner) + 64;
}

Status write_obj(const Mesh& mesh, TextBuilder& out) {
  if (Status status = check_names(mesh); !status) return status;
  out.begin(obj_size_estimate(mesh));
  if (!mesh.material_libraries.empty()) {
    // One line: readers that follow the spec split it into names, the others (some take the
    // rest of the line as one name) get the line as it was read.
    std::size_t length = 8;
    for (const std::string& name : mesh.material_libraries) length += name.size() + 1;
    out.ensure(length);
    out.put("mtllib");
    for (const std::string& name : mesh.material_libraries) {
      out.put(' ');
      out.put(std::string_view(name));
    }
    out.put('\n');
  }
  const float* p = mesh.positions.data();
  const std::size_t components = mesh.color_components;
  const float* color = mesh.colors.data();
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v, p += 3) {
    out.ensure(kMaxObjVertexLine);
    out.put("v ");
    out.put(p[0]);
    out.put(' ');
    out.put(p[1]);
    out.put(' ');
    out.put(p[2]);
    for (std::size_t c = 0; c < components; ++c, ++color) {
      out.put(' ');
      out.put(*color);
    }
    out.put('\n');
  }
  for (std::size_t t = 0; t < mesh.uv_count(); ++t) {
    out.ensure(kMaxObjVertexLine);
    out.put("vt ");
    out.put(mesh.uvs[2 * t]);
    out.put(' ');
    out.put(mesh.uvs[2 * t + 1]);
    out.put('\n');
  }
  for (std::size_t n = 0; n < mesh.normal_count(); ++n) {
    out.ensure(kMaxObjVertexLine);
    out.put("vn ");
    out.put_xyz_line(&mesh.normals[3 * n]);
  }
  const bool has_uvs = mesh.has_uvs();
  const bool has_normals = mesh.has_normals();
  const bool has_materials = mesh.has_materials();
  std::vector<bool> material_used(mesh.material_names.size(), false);
  uint32_t current_material = kNoAttribute;  // none until the first usemtl
  const uint32_t* t = mesh.triangles.data();
  for (std::size_t f = 0; f < mesh.face_count(); ++f, t += 3) {
    if (has_materials && mesh.face_materials[f] != current_material) {
      current_material = mesh.face_materials[f];
      if (current_material == kNoAttribute) {
        out.ensure(8);
        out.put("usemtl\n");  // back to no material
      } else {
        const std::string& name = mesh.material_names[current_material];
        material_used[current_material] = true;
        out.ensure(name.size() + 8);
        out.put("usemtl ");
        out.put(std::string_view(name));
        out.put('\n');
      }
    }
    out.ensure(kMaxObjFaceLine);
    out.put('f');
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t corner = 3 * f + k;
      out.put(' ');
      out.put(uint64_t{t[k]} + 1);
      const uint32_t uv = has_uvs ? mesh.uv_indices[corner] : kNoAttribute;
      const uint32_t normal = has_normals ? mesh.normal_indices[corner] : kNoAttribute;
      if (uv != kNoAttribute) {
        out.put('/');
        out.put(uint64_t{uv} + 1);
      }
      if (normal != kNoAttribute) {
        out.put(uv != kNoAttribute ? std::string_view("/") : std::string_view("//"));
        out.put(uint64_t{normal} + 1);
      }
    }
    out.put('\n');
  }
  // Materials no face uses (a level of detail may have lost their faces) are still named, so
  // that the table survives.
  for (std::size_t m = 0; m < mesh.material_names.size(); ++m) {
    if (material_used[m]) continue;
    out.ensure(mesh.material_names[m].size() + 8);
    out.put("usemtl ");
    out.put(std::string_view(mesh.material_names[m]));
    out.put('\n');
  }
  out.finish();
  return Status::ok();
}

// ---------------------------------------------------------------------------------------
// OFF

// A float colour component, written so that it can never be taken for an integer 0..255
// (the reader decides per file, as Geomview's colour specification reads).
void put_float_color(TextBuilder& out, float value) {
  char buffer[kMaxFloatChars + 2];
  char* end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
  const std::string_view text(buffer, static_cast<std::size_t>(end - buffer));
  out.put(text);
  if (text.find_first_of(".eE") == std::string_view::npos) out.put(".0");
}

// The vertices an OFF file gets: each input vertex once per distinct combination of
// (texture coordinate entry, normal entry) at its corners. The first combination keeps the
// vertex's number; further ones are appended.
struct OffVertices {
  std::vector<uint32_t> source;     // input vertex of each output vertex
  std::vector<uint32_t> uv;         // table entry of each output vertex, or kNoAttribute
  std::vector<uint32_t> normal;     // same for normals
  std::vector<uint32_t> triangles;  // the faces over the output vertices
};

OffVertices split_for_off(const Mesh& mesh, bool with_uvs, bool with_normals) {
  const std::size_t vertices = mesh.vertex_count();
  OffVertices out;
  out.source.resize(vertices);
  for (std::size_t v = 0; v < vertices; ++v) out.source[v] = static_cast<uint32_t>(v);
  out.uv.assign(vertices, kNoAttribute);
  out.normal.assign(vertices, kNoAttribute);
  out.triangles.resize(mesh.triangles.size());
  std::vector<bool> claimed(vertices, false);
  // (vertex, uv entry, normal entry) -> output vertex, for the copies.
  struct KeyHash {
    std::size_t operator()(const std::array<uint32_t, 3>& key) const {
      return (std::size_t{key[0]} * 0x9E3779B97F4A7C15ull) ^ (std::size_t{key[1]} << 21) ^
             std::size_t{key[2]};
    }
  };
  std::unordered_map<std::array<uint32_t, 3>, uint32_t, KeyHash> copies;
  for (std::size_t c = 0; c < mesh.triangles.size(); ++c) {
    const uint32_t v = mesh.triangles[c];
    const uint32_t uv = with_uvs ? mesh.uv_indices[c] : kNoAttribute;
    const uint32_t normal = with_normals ? mesh.normal_indices[c] : kNoAttribute;
    if (!claimed[v]) {
      claimed[v] = true;
      out.uv[v] = uv;
      out.normal[v] = normal;
      out.triangles[c] = v;
      continue;
    }
    if (out.uv[v] == uv && out.normal[v] == normal) {
      out.triangles[c] = v;
      continue;
    }
    auto [it, inserted] =
        copies.try_emplace({v, uv, normal}, static_cast<uint32_t>(out.source.size()));
    if (inserted) {
      out.source.push_back(v);
      out.uv.push_back(uv);
      out.normal.push_back(normal);
    }
    out.triangles[c] = it->second;
  }
  return out;
}

Status write_off(const Mesh& mesh, TextBuilder& out) {
  const bool with_colors = mesh.has_colors();
  const bool with_uvs = mesh.has_uvs();
  const bool with_normals = mesh.has_normals();
  OffVertices vertices = split_for_off(mesh, with_uvs, with_normals);
  if (vertices.source.size() > std::numeric_limits<uint32_t>::max()) {
    return Status(ErrorCode::kResourceLimit, "too many vertices for off after splitting seams");
  }
  const bool byte_colors = with_colors && colors_are_bytes(mesh.colors);
  const std::size_t components = mesh.color_components;
  // As obj_size_estimate: 13 characters a value, face lines bounded by their digits.
  const std::size_t values_per_vertex =
      3 + (with_normals ? 3 : 0) + (with_colors ? components : 0) + (with_uvs ? 2 : 0);
  out.begin(vertices.source.size() * (1 + values_per_vertex * 13) +
            mesh.face_count() * (3 + 3 * (1 + decimal_digits(vertices.source.size()))) + 64);
  // Geomview's keyword: [ST][C][N]OFF, the vertex fields in the order N, C, ST.
  out.ensure(8 + 2 * (kMaxIndexChars + 1) + 3);
  if (with_uvs) out.put("ST");
  if (with_colors) out.put('C');
  if (with_normals) out.put('N');
  out.put("OFF\n");
  out.put(uint64_t{vertices.source.size()});
  out.put(' ');
  out.put(uint64_t{mesh.face_count()});
  out.put(" 0\n");
  // A corner without a normal (texture coordinate) among corners with one: NaN, which the
  // reader takes for none. An unused vertex gets zeros.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float none_values[3] = {nan, nan, nan};
  const float zeros[3] = {0.0f, 0.0f, 0.0f};
  std::vector<bool> used(vertices.source.size(), false);
  for (uint32_t v : vertices.triangles) used[v] = true;
  for (std::size_t v = 0; v < vertices.source.size(); ++v) {
    const uint32_t source = vertices.source[v];
    out.ensure(kMaxVertexLine + 2 * (kMaxFloatChars + 3) + 4 * (kMaxFloatChars + 3) +
               3 * (kMaxFloatChars + 1));
    const float* p = &mesh.positions[3 * std::size_t{source}];
    out.put(p[0]);
    out.put(' ');
    out.put(p[1]);
    out.put(' ');
    out.put(p[2]);
    if (with_normals) {
      const uint32_t entry = vertices.normal[v];
      const float* n = entry != kNoAttribute ? &mesh.normals[3 * std::size_t{entry}]
                                             : (used[v] ? none_values : zeros);
      for (int k = 0; k < 3; ++k) {
        out.put(' ');
        out.put(n[k]);
      }
    }
    if (with_colors) {
      const float* color = &mesh.colors[components * source];
      for (std::size_t k = 0; k < components; ++k) {
        out.put(' ');
        if (byte_colors) {
          out.put(uint64_t{color_byte(color[k])});
        } else {
          put_float_color(out, color[k]);
        }
      }
    }
    if (with_uvs) {
      const uint32_t entry = vertices.uv[v];
      const float* uv = entry != kNoAttribute ? &mesh.uvs[2 * std::size_t{entry}]
                                              : (used[v] ? none_values : zeros);
      for (int k = 0; k < 2; ++k) {
        out.put(' ');
        out.put(uv[k]);
      }
    }
    out.put('\n');
  }
  const uint32_t* t = vertices.triangles.data();
  for (std::size_t f = 0; f < mesh.face_count(); ++f, t += 3) {
    out.ensure(kMaxFaceLine);
    out.put("3 ");
    out.put_index_line(t, 0);
  }
  out.finish();
  return Status::ok();
}

// ---------------------------------------------------------------------------------------
// PLY

Status write_ply(const Mesh& mesh, TextBuilder& out) {
  // PLY "int" indices are signed 32-bit.
  if (mesh.vertex_count() > static_cast<std::size_t>(std::numeric_limits<int32_t>::max())) {
    return Status(ErrorCode::kResourceLimit, "too many vertices for ply int indices");
  }
  if (mesh.material_names.size() > static_cast<std::size_t>(std::numeric_limits<int32_t>::max())) {
    return Status(ErrorCode::kResourceLimit, "too many materials for ply int indices");
  }
  if (Status status = check_names(mesh); !status) return status;
  const bool with_colors = mesh.has_colors();
  const bool byte_colors = with_colors && colors_are_bytes(mesh.colors);
  std::vector<uint32_t> vertex_uvs, vertex_normals;
  const bool with_uvs = mesh.has_uvs();
  const bool with_normals = mesh.has_normals();
  const bool uvs_per_vertex =
      with_uvs && per_vertex_entries(mesh, mesh.uv_indices, mesh.uvs, 2, vertex_uvs);
  const bool normals_per_vertex =
      with_normals &&
      per_vertex_entries(mesh, mesh.normal_indices, mesh.normals, 3, vertex_normals);
  const bool with_materials = mesh.has_materials();

  std::string header = "ply\nformat binary_little_endian 1.0\n";
  for (const std::string& name : mesh.material_libraries)
    header += "comment pm_mtllib " + name + "\n";
  // Names no face uses are kept too (a level of detail may have lost their faces).
  for (const std::string& name : mesh.material_names)
    header += "comment pm_material " + name + "\n";
  header += "element vertex " + std::to_string(mesh.vertex_count()) +
            "\n"
            "property float x\n"
            "property float y\n"
            "property float z\n";
  const char* color_names[4] = {"red", "green", "blue", "alpha"};
  for (uint32_t k = 0; k < mesh.color_components; ++k) {
    header +=
        std::string("property ") + (byte_colors ? "uchar " : "float ") + color_names[k] + "\n";
  }
  if (normals_per_vertex) header += "property float nx\nproperty float ny\nproperty float nz\n";
  if (uvs_per_vertex) header += "property float s\nproperty float t\n";
  header += "element face " + std::to_string(mesh.face_count()) +
            "\n"
            "property list uchar int vertex_indices\n";
  if (with_uvs && !uvs_per_vertex) header += "property list uchar float texcoord\n";
  if (with_normals && !normals_per_vertex) header += "property list uchar float corner_normals\n";
  if (with_materials) header += "property int pm_material\n";
  header += "end_header\n";

  const std::size_t vertex_size = 12 + mesh.color_components * (byte_colors ? 1 : 4) +
                                  (normals_per_vertex ? 12 : 0) + (uvs_per_vertex ? 8 : 0);
  const std::size_t face_size = 13 + (with_uvs && !uvs_per_vertex ? 25 : 0) +
                                (with_normals && !normals_per_vertex ? 37 : 0) +
                                (with_materials ? 4 : 0);
  out.begin(header.size() + mesh.vertex_count() * vertex_size + mesh.face_count() * face_size);
  out.ensure(header.size());
  out.put(header);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float zeros[3] = {0.0f, 0.0f, 0.0f};
  const float none_values[3] = {nan, nan, nan};
  std::vector<bool> used;
  if (normals_per_vertex || uvs_per_vertex) {
    used.assign(mesh.vertex_count(), false);
    for (uint32_t v : mesh.triangles) used[v] = true;
  }
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    out.ensure(vertex_size);  // a no-op but with a sink: begin() reserved it all
    for (int k = 0; k < 3; ++k) out.put_f32(mesh.positions[3 * v + k]);
    for (uint32_t k = 0; k < mesh.color_components; ++k) {
      const float value = mesh.colors[mesh.color_components * v + k];
      if (byte_colors) {
        out.put_u8(color_byte(value));
      } else {
        out.put_f32(value);
      }
    }
    // A vertex whose corners have none gets NaN (read back as none); a vertex no corner
    // uses gets zeros: its value is never looked up.
    if (normals_per_vertex) {
      const uint32_t entry = vertex_normals[v];
      const float* n = entry != kNoAttribute ? &mesh.normals[3 * std::size_t{entry}]
                                             : (used[v] ? none_values : zeros);
      for (int k = 0; k < 3; ++k) out.put_f32(n[k]);
    }
    if (uvs_per_vertex) {
      const uint32_t entry = vertex_uvs[v];
      const float* uv = entry != kNoAttribute ? &mesh.uvs[2 * std::size_t{entry}]
                                              : (used[v] ? none_values : zeros);
      for (int k = 0; k < 2; ++k) out.put_f32(uv[k]);
    }
  }
  // Writes one face's per-corner list: empty when no corner has a value, else `dims` floats
  // per corner, NaN for a corner without.
  auto put_corner_list = [&out, nan](const uint32_t* entries, const std::vector<float>& table,
                                     int dims) {
    if (entries[0] == kNoAttribute && entries[1] == kNoAttribute && entries[2] == kNoAttribute) {
      out.put_u8(0);
      return;
    }
    out.put_u8(static_cast<uint8_t>(3 * dims));
    for (int k = 0; k < 3; ++k) {
      for (int d = 0; d < dims; ++d) {
        out.put_f32(entries[k] == kNoAttribute ? nan : table[std::size_t{entries[k]} * dims + d]);
      }
    }
  };
  const uint32_t* t = mesh.triangles.data();
  for (std::size_t f = 0; f < mesh.face_count(); ++f, t += 3) {
    out.ensure(face_size);
    out.put_u8(3);
    out.put_u32(t[0]);
    out.put_u32(t[1]);
    out.put_u32(t[2]);
    if (with_uvs && !uvs_per_vertex) put_corner_list(&mesh.uv_indices[3 * f], mesh.uvs, 2);
    if (with_normals && !normals_per_vertex)
      put_corner_list(&mesh.normal_indices[3 * f], mesh.normals, 3);
    if (with_materials) {
      const uint32_t material = mesh.face_materials[f];
      out.put_u32(material == kNoAttribute ? 0xFFFFFFFFu : material);  // -1: none
    }
  }
  out.finish();
  return Status::ok();
}

Status write_stl(const Mesh& mesh, TextBuilder& out) {
  if (mesh.face_count() > std::numeric_limits<uint32_t>::max()) {
    return Status(ErrorCode::kResourceLimit, "too many faces for binary stl");
  }
  out.begin(84 + mesh.face_count() * 50);
  out.ensure(84);
  // The header must not start with "solid", which would make readers take it for ASCII STL.
  std::string header = "binary stl written by pm";
  header.resize(80, ' ');
  out.put(header);
  out.put_u32(static_cast<uint32_t>(mesh.face_count()));
  const float* positions = mesh.positions.data();
  const uint32_t* t = mesh.triangles.data();
  for (std::size_t f = 0; f < mesh.face_count(); ++f, t += 3) {
    out.ensure(50);
    const float* a = positions + 3 * std::size_t{t[0]};
    const float* b = positions + 3 * std::size_t{t[1]};
    const float* c = positions + 3 * std::size_t{t[2]};
    // The facet normal, by the right-hand rule; zero for a degenerate triangle.
    const double ab[3] = {double{b[0]} - a[0], double{b[1]} - a[1], double{b[2]} - a[2]};
    const double ac[3] = {double{c[0]} - a[0], double{c[1]} - a[1], double{c[2]} - a[2]};
    double normal[3] = {ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2],
                        ab[0] * ac[1] - ab[1] * ac[0]};
    const double length =
        std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    for (double& component : normal)
      component = length > 0 && std::isfinite(length) ? component / length : 0.0;
    for (double component : normal) out.put_f32(static_cast<float>(component));
    for (const float* corner : {a, b, c}) {
      out.put_f32(corner[0]);
      out.put_f32(corner[1]);
      out.put_f32(corner[2]);
    }
    out.put_u16(0);  // attribute byte count
  }
  out.finish();
  return Status::ok();
}

}  // namespace

namespace {

// The serialization of `mesh` into `out` (write_mesh_to_memory's and write_mesh_to_sink's);
// glTF straight into `whole` when it is not null (write_mesh_to_memory's string).
Status write_mesh_with(const Mesh& mesh, MeshFormat format, TextBuilder& out,
                       std::string* whole) {
  if (format == MeshFormat::kUnknown) {
    return Status(ErrorCode::kUnsupportedFormat,
                  "unknown mesh format (use .obj .ply .off .stl .gltf .glb)");
  }
  if (Status status = validate(mesh); !status) return status;
  switch (format) {
    case MeshFormat::kObj:
      return write_obj(mesh, out);
    case MeshFormat::kOff:
      return write_off(mesh, out);
    case MeshFormat::kPly:
      return write_ply(mesh, out);
    case MeshFormat::kStl:
      return write_stl(mesh, out);
    case MeshFormat::kGltf:
    case MeshFormat::kGlb: {
      GltfWriteOptions options;
      options.binary = format == MeshFormat::kGlb;
      if (whole != nullptr) return write_gltf({{&mesh, 0}}, options, *whole);
      // Whole first (its JSON names the buffer's length), then given out as the others are.
      std::string gltf;
      if (Status status = write_gltf({{&mesh, 0}}, options, gltf); !status) return status;
      out.begin(0);
      for (std::size_t at = 0; at < gltf.size(); at += kSinkPiece) {
        const std::size_t piece = std::min(kSinkPiece, gltf.size() - at);
        out.ensure(piece);
        out.put(std::string_view(gltf).substr(at, piece));
      }
      out.finish();
      return Status::ok();
    }
    case MeshFormat::kUnknown:
      break;
  }
  return Status(ErrorCode::kInternal, "unhandled mesh format");
}

}  // namespace

Status write_mesh_to_memory(const Mesh& mesh, MeshFormat format, std::string& bytes) {
  return detail::no_throw([&]() -> Status {
    TextBuilder out(bytes);
    return write_mesh_with(mesh, format, out, &bytes);
  });
}

Status write_mesh_to_sink(const Mesh& mesh, MeshFormat format, const MeshByteSink& sink) {
  return detail::no_throw([&]() -> Status {
    if (!sink) return Status(ErrorCode::kInvalidArgument, "no sink to write the mesh to");
    std::string buffer;
    TextBuilder out(buffer, &sink);
    try {
      return write_mesh_with(mesh, format, out, nullptr);
    } catch (SinkFailed& failed) {
      return std::move(failed.status);
    }
  });
}

}  // namespace pm
