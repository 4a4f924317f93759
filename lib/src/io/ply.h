// A PLY file's header as the PLY reader sees it (Turk 1994, "The PLY polygon file format"):
// parse_ply_header and assign_ply_roles (ply_header.cpp) read it, read_ply (ply_reader.cpp)
// reads the body it describes. Internal to io/.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "pm/mesh_io.h"
#include "pm/status.h"

namespace pm::detail {

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

inline std::size_t ply_type_size(PlyType type) {
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

inline bool is_ply_integer(PlyType type) {
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

// Reads and checks the header (ply_header.cpp).
Status parse_ply_header(std::string_view bytes, PlyHeader& header);

// Gives each property its role (ply_header.cpp).
void assign_ply_roles(PlyHeader& header, ReadReport& report);

}  // namespace pm::detail
