// glTF 2.0 writer: one level as a plain mesh, or a chain of levels in one file sharing one
// vertex buffer (glTF 2.0 specification, Khronos 2017/2021; pm/gltf.h has the contract).
//
// Why one vertex buffer serves every level: a half-edge collapse never moves a vertex, so
// every level is made of the input's own vertices (Hoppe 1996, "Progressive Meshes", §3), and
// a glTF vertex (a position with the corner's texture coordinate, normal and colour: a wedge)
// of a coarse level is a vertex of the finer ones. The vertices are numbered in the order the
// levels first use them, coarse to fine, so that level k's indices name a prefix of the
// buffer (what meshoptimizer's README recommends for levels of detail); each level has its
// own index bufferView, one accessor per material (one primitive each, so one draw call each).
// MSFT_lod (Microsoft's vendor extension, "MSFT_lod", 2017) ties the levels together on the
// finest level's node, which is the only one in the scene: a loader without the extension
// shows the finest level. Its MSFT_screencoverage hints come from the levels' error bounds.
//
// KHR_mesh_quantization (Khronos, 2019): positions as unsigned 16-bit integers on a grid that
// the node's translation and uniform scale map back, normals as normalized 8-bit integers,
// texture coordinates in [0, 1] as normalized 16-bit integers. Vertex attribute elements
// start on 4-byte boundaries (§3.6.2.4), hence byteStride 8 for positions and 4 for normals.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include "io/gltf_glb.h"
#include "core/no_throw.h"
#include "io/gltf_names.h"
#include "pm/gltf.h"

namespace pm {
namespace {

using Json = nlohmann::ordered_json;

constexpr int kFloat = 5126, kUnsignedShort = 5123, kUnsignedInt = 5125, kByte = 5120;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

// The vertical resolution the screen-coverage hints assume: a level is shown while its
// error bound projects to at most one pixel of a screen this tall.
constexpr double kHintScreenPixels = 1080;

uint32_t bits_of(float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, 4);
  return bits;
}

struct BitsHash {
  std::size_t operator()(const std::array<uint32_t, 12>& key) const {
    uint64_t h = 0x9E3779B97F4A7C15ull;
    for (uint32_t k : key) h = (h ^ k) * 0x100000001B3ull + (h >> 29);
    return static_cast<std::size_t>(h);
  }
};

// No value: a NaN bit pattern, which no written value has (values are checked finite).
constexpr uint32_t kNone = 0xFFFFFFFFu;

// The glTF vertices of all levels: one per distinct (position, colour, texture coordinate,
// normal), numbered in order of first use.
struct SharedVertices {
  std::vector<float> positions, colors, uvs, normals;
  std::unordered_map<std::array<uint32_t, 12>, uint32_t, BitsHash> ids;

  uint32_t add(const std::array<uint32_t, 12>& key, const float* position, const float* color, uint32_t color_components,
               const float* uv, const float* normal) {
    auto [it, inserted] = ids.try_emplace(key, static_cast<uint32_t>(positions.size() / 3));
    if (inserted) {
      positions.insert(positions.end(), position, position + 3);
      if (color_components) colors.insert(colors.end(), color, color + color_components);
      static const float kNoUv[2] = {0, 0};
      static const float kNoNormal[3] = {0, 0, 1};
      uvs.insert(uvs.end(), uv ? uv : kNoUv, (uv ? uv : kNoUv) + 2);
      normals.insert(normals.end(), normal ? normal : kNoNormal, (normal ? normal : kNoNormal) + 3);
    }
    return it->second;
  }
  std::size_t count() const { return positions.size() / 3; }
};

// One primitive of a level: faces of one material, with or without texture coordinates and
// normals (a primitive's attributes are all-or-none).
struct PrimitiveKey {
  uint32_t material;  // index into the written materials, or kNone
  bool uvs, normals;
  bool operator<(const PrimitiveKey& o) const {
    return std::tie(material, uvs, normals) < std::tie(o.material, o.uvs, o.normals);
  }
};

// glTF requires unit normals (§3.7.2.1, "NORMAL": normalized); a stored normal that is not
// (an OBJ's may be any length) is scaled to unit length, a zero one replaced by +z. One within
// 1e-6 of unit length is written as it is, so that unit normals keep their bits.
void unit_normal(const float* in, float* out) {
  const double length = std::sqrt(double(in[0]) * in[0] + double(in[1]) * in[1] + double(in[2]) * in[2]);
  if (std::fabs(length - 1) <= 1e-6) {
    std::copy(in, in + 3, out);
  } else if (length > 0) {
    for (int i = 0; i < 3; ++i) out[i] = static_cast<float>(in[i] / length);
  } else {
    out[0] = 0, out[1] = 0, out[2] = 1;
  }
}

class BinaryBuilder {
 public:
  // Starts a bufferView on a 4-byte boundary; returns its index.
  int begin_view(Json& views, std::size_t byte_stride, int target) {
    while (bytes_.size() % 4) bytes_.push_back('\0');
    Json view = {{"buffer", 0}, {"byteOffset", bytes_.size()}, {"byteLength", 0}};
    if (byte_stride) view["byteStride"] = byte_stride;
    if (target) view["target"] = target;
    views.push_back(view);
    view_start_ = bytes_.size();
    return static_cast<int>(views.size() - 1);
  }
  void end_view(Json& views) { views.back()["byteLength"] = bytes_.size() - view_start_; }
  template <typename T>
  void put(T value) {
    const char* p = reinterpret_cast<const char*>(&value);
    bytes_.append(p, sizeof value);  // little-endian hosts only, as the rest of pm's binary IO
  }
  void pad(std::size_t n) { bytes_.append(n, '\0'); }
  void append(std::string_view data) { bytes_.append(data); }
  std::size_t view_offset() const { return bytes_.size() - view_start_; }
  std::string& bytes() { return bytes_; }

 private:
  std::string bytes_;
  std::size_t view_start_ = 0;
};

// Normalized 8-bit normal whose decoded length is nearest 1 among the roundings of each
// component down and up: plain rounding can be off by 0.0068 in length, past the 0.00674 the
// Khronos validator tolerates.
std::array<int8_t, 3> quantize_normal(const float* n) {
  std::array<int8_t, 3> best{};
  double best_error = std::numeric_limits<double>::infinity();
  for (int choice = 0; choice < 8; ++choice) {
    std::array<int8_t, 3> q;
    double length2 = 0;
    for (int i = 0; i < 3; ++i) {
      const double scaled = std::clamp(double(n[i]) * 127.0, -127.0, 127.0);
      const double rounded = (choice >> i & 1) ? std::ceil(scaled) : std::floor(scaled);
      q[i] = static_cast<int8_t>(std::clamp(rounded, -127.0, 127.0));
      length2 += (q[i] / 127.0) * (q[i] / 127.0);
    }
    const double error = std::fabs(std::sqrt(length2) - 1);
    if (error < best_error) best_error = error, best = q;
  }
  return best;
}

std::string base64(std::string_view bytes) {
  static const char* kDigits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
    if (i + 1 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) v |= uint8_t(bytes[i + 2]);
    out += kDigits[v >> 18 & 63];
    out += kDigits[v >> 12 & 63];
    out += i + 1 < bytes.size() ? kDigits[v >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? kDigits[v & 63] : '=';
  }
  return out;
}

// ---------------------------------------------------------------------------------------
// Materials copied from a source file (pmdec --material-from): the definitions of the
// materials named, with the textures, samplers and images they use, renumbered.

class MaterialCopier {
 public:
  Status load(const GltfMaterialSource& source) {
    std::string_view json = source.bytes;
    if (detail::is_glb(source.bytes)) {
      detail::GlbChunks chunks;
      if (Status s = detail::split_glb(source.bytes, chunks); !s) return s;
      json = chunks.json;
      binary_ = std::string(chunks.binary);
    }
    document_ = Json::parse(json.begin(), json.end(), nullptr, false);
    if (!document_.is_object()) return Status(ErrorCode::kParseError, "material source: not a glTF JSON object");
    image_directory_ = source.image_directory;
    std::vector<std::string> raw;
    if (document_.contains("materials") && document_["materials"].is_array())
      for (const Json& material : document_["materials"])
        raw.push_back(material.is_object() && material.contains("name") && material["name"].is_string()
                          ? material["name"].get<std::string>()
                          : "");
    const std::vector<std::string> names = detail::unique_material_names(raw);
    for (std::size_t i = 0; i < names.size(); ++i) by_name_[names[i]] = i;
    return Status::ok();
  }

  // The definition for `name`, its textures renumbered into `out`; {"name": name} when the
  // source has no such material.
  Status material(const std::string& name, Json& out, BinaryBuilder& binary, Json& views, Json& definition) {
    const auto found = by_name_.find(name);
    if (found == by_name_.end()) {
      definition = {{"name", name}};
      return Status::ok();
    }
    definition = document_["materials"][found->second];
    return renumber_textures(definition, out, binary, views);
  }

  // Extension names the copied objects use.
  const std::set<std::string>& extensions() const { return extensions_; }
  bool required(const std::string& extension) const {
    if (!document_.contains("extensionsRequired") || !document_["extensionsRequired"].is_array()) return false;
    for (const Json& e : document_["extensionsRequired"])
      if (e == extension) return true;
    return false;
  }

 private:
  void note_extensions(const Json& value) {
    if (value.is_object()) {
      for (auto it = value.begin(); it != value.end(); ++it) {
        if (it.key() == "extensions" && it.value().is_object())
          for (auto e = it.value().begin(); e != it.value().end(); ++e) extensions_.insert(e.key());
        note_extensions(it.value());
      }
    } else if (value.is_array()) {
      for (const Json& item : value) note_extensions(item);
    }
  }

  // Every textureInfo ({"index": texture, ...} under a key ending in "Texture", the core's
  // and the KHR_materials_ extensions' convention) points at a copied texture.
  Status renumber_textures(Json& value, Json& out, BinaryBuilder& binary, Json& views) {
    if (value.is_object()) {
      for (auto it = value.begin(); it != value.end(); ++it) {
        const std::string& key = it.key();
        const bool texture_info = key.size() >= 7 && (key.compare(key.size() - 7, 7, "Texture") == 0 ||
                                                       key.compare(key.size() - 7, 7, "texture") == 0);
        if (texture_info && it.value().is_object() && it.value().contains("index") &&
            it.value()["index"].is_number_unsigned()) {
          std::size_t texture = 0;
          if (Status s = copy_texture(it.value()["index"].get<std::size_t>(), out, binary, views, texture); !s)
            return s;
          it.value()["index"] = texture;
        }
        if (Status s = renumber_textures(it.value(), out, binary, views); !s) return s;
      }
    } else if (value.is_array()) {
      for (Json& item : value)
        if (Status s = renumber_textures(item, out, binary, views); !s) return s;
    }
    if (value.is_object() && value.contains("extensions")) note_extensions(value);
    return Status::ok();
  }

  static Status missing(const std::string& what) {
    return Status(ErrorCode::kParseError, "material source: " + what + " does not exist");
  }

  // The source's `kind`[index], which must be an object.
  Status source_object(const char* kind, std::size_t index, Json& item) {
    if (!document_.contains(kind) || !document_[kind].is_array() || index >= document_[kind].size())
      return missing(std::string(kind) + " " + std::to_string(index));
    item = document_[kind][index];
    if (!item.is_object())
      return Status(ErrorCode::kParseError,
                    std::string("material source: ") + kind + " " + std::to_string(index) + " is not an object");
    return Status::ok();
  }

  Status copy_texture(std::size_t index, Json& out, BinaryBuilder& binary, Json& views, std::size_t& copy) {
    if (auto found = textures_.find(index); found != textures_.end()) return copy = found->second, Status::ok();
    Json texture;
    if (Status s = source_object("textures", index, texture); !s) return s;
    if (texture.contains("sampler") && texture["sampler"].is_number_unsigned()) {
      const std::size_t sampler = texture["sampler"].get<std::size_t>();
      if (auto found = samplers_.find(sampler); found != samplers_.end()) {
        texture["sampler"] = found->second;
      } else {
        Json copied;
        if (Status s = source_object("samplers", sampler, copied); !s) return s;
        note_extensions(copied);
        out["samplers"].push_back(copied);
        texture["sampler"] = samplers_[sampler] = out["samplers"].size() - 1;
      }
    }
    // "source" in the texture and in its extensions (KHR_texture_basisu, EXT_texture_webp).
    auto renumber_source = [&](Json& holder) -> Status {
      if (!holder.contains("source") || !holder["source"].is_number_unsigned()) return Status::ok();
      std::size_t image = 0;
      if (Status s = copy_image(holder["source"].get<std::size_t>(), out, binary, views, image); !s) return s;
      holder["source"] = image;
      return Status::ok();
    };
    if (Status s = renumber_source(texture); !s) return s;
    if (texture.contains("extensions") && texture["extensions"].is_object())
      for (auto it = texture["extensions"].begin(); it != texture["extensions"].end(); ++it)
        if (it.value().is_object())
          if (Status s = renumber_source(it.value()); !s) return s;
    note_extensions(texture);
    out["textures"].push_back(texture);
    copy = textures_[index] = out["textures"].size() - 1;
    return Status::ok();
  }

  // An image by URI: the same URI (relative ones from the output's directory); an image in a
  // bufferView of the source's GLB BIN chunk: its bytes copied into this file's buffer.
  Status copy_image(std::size_t index, Json& out, BinaryBuilder& binary, Json& views, std::size_t& copy) {
    if (auto found = images_.find(index); found != images_.end()) return copy = found->second, Status::ok();
    Json image;
    if (Status s = source_object("images", index, image); !s) return s;
    if (image.contains("uri") && image["uri"].is_string()) {
      const std::string uri = image["uri"];
      const bool relative = uri.rfind("data:", 0) != 0 && uri.find("://") == std::string::npos &&
                            !uri.empty() && uri[0] != '/';
      if (relative && !image_directory_.empty()) image["uri"] = image_directory_ + "/" + uri;
    } else if (image.contains("bufferView") && image["bufferView"].is_number_unsigned()) {
      const std::size_t view = image["bufferView"].get<std::size_t>();
      if (!document_.contains("bufferViews") || view >= document_["bufferViews"].size())
        return missing("bufferView " + std::to_string(view));
      const Json& source_view = document_["bufferViews"][view];
      const uint64_t offset = source_view.value("byteOffset", uint64_t{0});
      const uint64_t length = source_view.value("byteLength", uint64_t{0});
      if (source_view.value("buffer", uint64_t{1}) != 0 || offset > binary_.size() || length > binary_.size() - offset)
        return Status(ErrorCode::kUnsupportedFormat,
                      "material source: image " + std::to_string(index) +
                          " is not in its GLB's BIN chunk, and pm copies only those");
      binary.begin_view(views, 0, 0);
      binary.append(std::string_view(binary_).substr(offset, length));
      binary.end_view(views);
      image["bufferView"] = views.size() - 1;
    }
    note_extensions(image);
    out["images"].push_back(image);
    copy = images_[index] = out["images"].size() - 1;
    return Status::ok();
  }

  Json document_;
  std::string binary_;
  std::string image_directory_;
  std::map<std::string, std::size_t> by_name_;
  std::map<std::size_t, std::size_t> textures_, samplers_, images_;
  std::set<std::string> extensions_;
};

bool all_finite(const std::vector<float>& values) {
  return std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); });
}

}  // namespace

Status write_gltf(const std::vector<GltfLevel>& levels, const GltfWriteOptions& options, std::string& bytes) {
  return detail::no_throw([&]() -> Status {
    if (levels.empty()) return Status(ErrorCode::kInvalidArgument, "no level to write");
    uint32_t color_components = 0;
    for (const GltfLevel& level : levels) {
      if (!level.mesh) return Status(ErrorCode::kInvalidArgument, "a level without a mesh");
      if (Status valid = validate_attributes(*level.mesh); !valid) return valid;
      const Mesh& m = *level.mesh;
      if (!all_finite(m.positions) || !all_finite(m.colors) || !all_finite(m.uvs) || !all_finite(m.normals))
        return Status(ErrorCode::kInvalidArgument, "non-finite value");
      if (&level != &levels.front() && m.color_components != color_components)
        return Status(ErrorCode::kInvalidArgument, "levels with different colour components");
      color_components = m.color_components;
    }

    // Materials by name, in order of first use over the levels.
    std::vector<std::string> material_names;
    std::map<std::string, uint32_t> material_ids;
    // Each level's faces as primitives; the shared vertices.
    SharedVertices vertices;
    std::vector<std::map<PrimitiveKey, std::vector<uint32_t>>> level_primitives(levels.size());
    for (std::size_t l = 0; l < levels.size(); ++l) {
      const Mesh& m = *levels[l].mesh;
      std::vector<uint32_t> material_of(m.material_names.size(), kNone);
      for (std::size_t f = 0; f < m.face_count(); ++f) {
        PrimitiveKey key{kNone, m.has_uvs(), m.has_normals()};
        if (m.has_materials() && m.face_materials[f] != kNoAttribute) {
          const uint32_t local = m.face_materials[f];
          if (material_of[local] == kNone) {
            auto [it, inserted] = material_ids.try_emplace(m.material_names[local], uint32_t(material_names.size()));
            if (inserted) material_names.push_back(m.material_names[local]);
            material_of[local] = it->second;
          }
          key.material = material_of[local];
        }
        for (int c = 0; c < 3; ++c) {
          key.uvs = key.uvs && m.uv_indices[3 * f + c] != kNoAttribute;
          key.normals = key.normals && m.normal_indices[3 * f + c] != kNoAttribute;
        }
        std::vector<uint32_t>& indices = level_primitives[l][key];
        for (int c = 0; c < 3; ++c) {
          const std::size_t corner = 3 * f + c;
          const uint32_t v = m.triangles[corner];
          const float* position = &m.positions[3 * std::size_t{v}];
          const float* color = color_components ? &m.colors[std::size_t{v} * color_components] : nullptr;
          const float* uv = key.uvs ? &m.uvs[2 * std::size_t{m.uv_indices[corner]}] : nullptr;
          float normal[3];
          if (key.normals) unit_normal(&m.normals[3 * std::size_t{m.normal_indices[corner]}], normal);
          std::array<uint32_t, 12> id;
          id.fill(kNone);
          for (int i = 0; i < 3; ++i) id[i] = bits_of(position[i]);
          for (uint32_t i = 0; i < color_components; ++i) id[3 + i] = bits_of(color[i]);
          if (uv) id[7] = bits_of(uv[0]), id[8] = bits_of(uv[1]);
          if (key.normals) id[9] = bits_of(normal[0]), id[10] = bits_of(normal[1]), id[11] = bits_of(normal[2]);
          indices.push_back(vertices.add(id, position, color, color_components, uv, key.normals ? normal : nullptr));
        }
      }
    }
    const std::size_t vertex_count = vertices.count();
    if (vertex_count == 0) return Status(ErrorCode::kInvalidArgument, "no faces to write");
    if (vertex_count > UINT32_MAX - 1) return Status(ErrorCode::kResourceLimit, "more than 2^32 - 1 vertices");
    bool any_uvs = false, any_normals = false;
    for (const auto& primitives : level_primitives)
      for (const auto& [key, indices] : primitives) any_uvs |= key.uvs, any_normals |= key.normals;

    Json document;
    document["asset"] = {{"version", "2.0"}, {"generator", std::string("pm ") + PM_VERSION_STRING}};
    Json views = Json::array(), accessors = Json::array();
    BinaryBuilder binary;

    // Vertex attributes: one accessor each, shared by every primitive of every level.
    Json attributes;
    double grid_scale = 1;
    std::array<double, 3> grid_origin{};
    {
      // POSITION: min and max are required (§3.7.2.1).
      std::array<float, 3> low, high;
      for (int i = 0; i < 3; ++i) {
        low[i] = high[i] = vertices.positions[i];
        for (std::size_t v = 0; v < vertex_count; ++v) {
          low[i] = std::min(low[i], vertices.positions[3 * v + i]);
          high[i] = std::max(high[i], vertices.positions[3 * v + i]);
        }
      }
      Json accessor = {{"bufferView", 0}, {"componentType", kFloat}, {"count", vertex_count}, {"type", "VEC3"}};
      if (options.quantize) {
        double extent = 0;
        for (int i = 0; i < 3; ++i) extent = std::max(extent, double(high[i]) - low[i]), grid_origin[i] = low[i];
        grid_scale = extent > 0 ? extent / 65535.0 : 1.0;
        accessor["bufferView"] = binary.begin_view(views, 8, kArrayBuffer);
        accessor["componentType"] = kUnsignedShort;
        std::array<uint16_t, 3> qlow{65535, 65535, 65535}, qhigh{0, 0, 0};
        for (std::size_t v = 0; v < vertex_count; ++v) {
          for (int i = 0; i < 3; ++i) {
            const double q = std::round((vertices.positions[3 * v + i] - grid_origin[i]) / grid_scale);
            const auto value = static_cast<uint16_t>(std::clamp(q, 0.0, 65535.0));
            qlow[i] = std::min(qlow[i], value), qhigh[i] = std::max(qhigh[i], value);
            binary.put(value);
          }
          binary.pad(2);
        }
        accessor["min"] = qlow;
        accessor["max"] = qhigh;
      } else {
        accessor["bufferView"] = binary.begin_view(views, 0, kArrayBuffer);
        for (float value : vertices.positions) binary.put(value);
        accessor["min"] = {double(low[0]), double(low[1]), double(low[2])};
        accessor["max"] = {double(high[0]), double(high[1]), double(high[2])};
      }
      binary.end_view(views);
      accessors.push_back(accessor);
      attributes["POSITION"] = accessors.size() - 1;
    }
    if (any_normals) {
      Json accessor = {{"componentType", kFloat}, {"count", vertex_count}, {"type", "VEC3"}};
      if (options.quantize) {
        accessor["bufferView"] = binary.begin_view(views, 4, kArrayBuffer);
        accessor["componentType"] = kByte;
        accessor["normalized"] = true;
        for (std::size_t v = 0; v < vertex_count; ++v) {
          for (int8_t q : quantize_normal(&vertices.normals[3 * v])) binary.put(q);
          binary.pad(1);
        }
      } else {
        accessor["bufferView"] = binary.begin_view(views, 0, kArrayBuffer);
        for (float value : vertices.normals) binary.put(value);
      }
      binary.end_view(views);
      accessors.push_back(accessor);
      attributes["NORMAL"] = accessors.size() - 1;
    }
    if (any_uvs) {
      Json accessor = {{"componentType", kFloat}, {"count", vertex_count}, {"type", "VEC2"}};
      const bool unit_range = std::all_of(vertices.uvs.begin(), vertices.uvs.end(), [](float t) { return t >= 0 && t <= 1; });
      accessor["bufferView"] = binary.begin_view(views, 0, kArrayBuffer);
      if (options.quantize && unit_range) {
        accessor["componentType"] = kUnsignedShort;
        accessor["normalized"] = true;
        for (float t : vertices.uvs) binary.put(static_cast<uint16_t>(std::lround(double(t) * 65535.0)));
      } else {
        for (float value : vertices.uvs) binary.put(value);
      }
      binary.end_view(views);
      accessors.push_back(accessor);
      attributes["TEXCOORD_0"] = accessors.size() - 1;
    }
    if (color_components) {
      Json accessor = {{"bufferView", binary.begin_view(views, 0, kArrayBuffer)}, {"componentType", kFloat},
                       {"count", vertex_count}, {"type", color_components == 4 ? "VEC4" : "VEC3"}};
      for (float value : vertices.colors) binary.put(value);
      binary.end_view(views);
      accessors.push_back(accessor);
      attributes["COLOR_0"] = accessors.size() - 1;
    }

    // Materials: definitions copied from the source, or names.
    Json materials = Json::array();
    Json copied_textures = Json::object();
    MaterialCopier copier;
    if (options.materials)
      if (Status s = copier.load(*options.materials); !s) return s;
    for (const std::string& name : material_names) {
      Json definition;
      if (options.materials) {
        if (Status s = copier.material(name, copied_textures, binary, views, definition); !s) return s;
      } else {
        definition = {{"name", name}};
      }
      materials.push_back(definition);
    }

    // Indices: one bufferView per level, finest first (the order of the nodes), one accessor
    // per primitive; 16-bit when every index fits below 65535 (the primitive restart value).
    const bool short_indices = vertex_count <= 65535;
    Json meshes = Json::array(), nodes = Json::array();
    for (std::size_t n = 0; n < levels.size(); ++n) {
      const std::size_t l = levels.size() - 1 - n;  // node n is level l: finest first
      const int view = binary.begin_view(views, 0, kElementArrayBuffer);
      Json primitives = Json::array();
      for (const auto& [key, indices] : level_primitives[l]) {
        Json accessor = {{"bufferView", view},
                         {"byteOffset", binary.view_offset()},
                         {"componentType", short_indices ? kUnsignedShort : kUnsignedInt},
                         {"count", indices.size()},
                         {"type", "SCALAR"}};
        for (uint32_t index : indices) short_indices ? binary.put(static_cast<uint16_t>(index)) : binary.put(index);
        if (short_indices && indices.size() % 2) binary.pad(2);  // the next accessor on 4 bytes
        accessors.push_back(accessor);
        Json primitive_attributes = {{"POSITION", attributes["POSITION"]}};
        if (key.normals) primitive_attributes["NORMAL"] = attributes["NORMAL"];
        if (key.uvs) primitive_attributes["TEXCOORD_0"] = attributes["TEXCOORD_0"];
        if (attributes.contains("COLOR_0")) primitive_attributes["COLOR_0"] = attributes["COLOR_0"];
        Json primitive = {{"attributes", primitive_attributes}, {"indices", accessors.size() - 1}};
        if (key.material != kNone) primitive["material"] = key.material;
        primitives.push_back(primitive);
      }
      binary.end_view(views);
      meshes.push_back({{"name", "level_" + std::to_string(n)}, {"primitives", primitives}});
      Json node = {{"name", "level_" + std::to_string(n)}, {"mesh", n}};
      if (options.quantize) {
        node["translation"] = grid_origin;
        node["scale"] = {grid_scale, grid_scale, grid_scale};
      }
      nodes.push_back(node);
    }
    std::vector<std::string> used, required;
    if (levels.size() > 1) {
      // MSFT_lod on the finest node, the coarser ones listed finest first; one screen-coverage
      // hint per level: the share of the screen's height the model's diagonal may cover before
      // the next coarser level's error bound would project to more than a pixel on a
      // kHintScreenPixels-high screen, squared (an area), 0 for the coarsest.
      Json ids = Json::array(), coverage = Json::array();
      double diagonal = 0;
      {
        double d2 = 0;
        for (int i = 0; i < 3; ++i) {
          float lo = vertices.positions[i], hi = lo;
          for (std::size_t v = 0; v < vertex_count; ++v)
            lo = std::min(lo, vertices.positions[3 * v + i]), hi = std::max(hi, vertices.positions[3 * v + i]);
          d2 += (double(hi) - lo) * (double(hi) - lo);
        }
        diagonal = std::sqrt(d2);
      }
      for (std::size_t n = 1; n < levels.size(); ++n) ids.push_back(n);
      double previous = 1;
      for (std::size_t n = 0; n < levels.size(); ++n) {
        double hint = 0;
        if (n + 1 < levels.size()) {
          const double coarser_error = levels[levels.size() - 2 - n].error;
          const double height_share = coarser_error > 0 ? diagonal / (coarser_error * kHintScreenPixels) : 1;
          hint = std::min(previous, std::min(1.0, height_share * height_share));
        }
        coverage.push_back(hint);
        previous = hint;
      }
      nodes[0]["extensions"] = {{"MSFT_lod", {{"ids", ids}}}};
      nodes[0]["extras"] = {{"MSFT_screencoverage", coverage}};
      used.push_back("MSFT_lod");
    }
    if (options.quantize) used.push_back("KHR_mesh_quantization"), required.push_back("KHR_mesh_quantization");
    for (const std::string& extension : copier.extensions()) {
      used.push_back(extension);
      if (copier.required(extension)) required.push_back(extension);
    }
    if (!used.empty()) document["extensionsUsed"] = used;
    if (!required.empty()) document["extensionsRequired"] = required;
    document["scene"] = 0;
    document["scenes"] = Json::array({{{"nodes", {0}}}});
    document["nodes"] = nodes;
    document["meshes"] = meshes;
    if (!materials.empty()) document["materials"] = materials;
    for (const char* kind : {"textures", "images", "samplers"})
      if (copied_textures.contains(kind)) document[kind] = copied_textures[kind];
    document["accessors"] = accessors;
    document["bufferViews"] = views;
    while (binary.bytes().size() % 4) binary.bytes().push_back('\0');
    Json buffer = {{"byteLength", binary.bytes().size()}};
    if (!options.binary) buffer["uri"] = "data:application/octet-stream;base64," + base64(binary.bytes());
    document["buffers"] = Json::array({buffer});
    const std::string json = document.dump();
    bytes = options.binary ? detail::make_glb(json, binary.bytes()) : json;
    return Status::ok();
  });
}

}  // namespace pm
