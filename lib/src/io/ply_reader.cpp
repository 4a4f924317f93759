// The PLY reader (read_ply below); its header is read by ply_header.cpp.
//
// PLY is not read through OpenMesh (any more) because its reader loses attributes: it
// truncates float colours to bytes, reads no per-corner texture coordinates and misplaces
// every later value of a face with any list besides vertex_indices; its header parser loops
// forever without end_header and misplaces binary data after a comment line.

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

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "io/mesh_readers.h"
#include "io/ply.h"
#include "io/reader_support.h"

namespace pm::detail {
namespace {

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

}  // namespace

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

}  // namespace pm::detail
