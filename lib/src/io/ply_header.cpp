// The PLY reader's header: its grammar, and what each property of the vertex and face
// elements is for (Turk 1994, "The PLY polygon file format"; ply_reader.cpp reads the body).
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "io/ply.h"
#include "io/reader_support.h"

namespace pm::detail {
namespace {

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

}  // namespace

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

}  // namespace pm::detail
