// glTF 2.0 reader: the default scene's triangles, merged into one Mesh (pm/gltf.h says what is
// kept). tinygltf (tiny_gltf_config.h) parses the JSON and loads the buffers; everything it
// leaves unchecked is checked here before a byte is read: the GLB container (gltf_glb.h),
// bufferViews against their buffers, accessors against their bufferViews with their strides
// (glTF 2.0 specification, Khronos 2017/2021, §3.6.2 "Accessors"), sparse indices, vertex
// indices against the vertex count, the node hierarchy for cycles (§3.5.2), and the faces the
// scene instances against a limit, before any of them is built.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <new>
#include <string>
#include <unordered_map>
#include <vector>

#include "io/gltf_glb.h"
#include "io/gltf_names.h"
#include "io/tiny_gltf_config.h"
#include "pm/gltf.h"

namespace pm {
namespace {

Status parse_error(const std::string& message) { return Status(ErrorCode::kParseError, message); }

// ---------------------------------------------------------------------------------------
// Accessors (§3.6.2): element i, component c of an accessor is at
//   buffer[bufferView.byteOffset + accessor.byteOffset + i * stride + c * component_size],
// where stride is the bufferView's byteStride, or the element's size when it has none.
// Integer components are converted as §3.11's table of normalized values says when the
// accessor is normalized (signed: max(c / (2^(n-1) - 1), -1); unsigned: c / (2^n - 1)), and
// to their value otherwise (KHR_mesh_quantization's non-normalized integers).

int component_size(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;
  }
}

int components_of(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    default:
      return 0;
  }
}

// One component at p, as a double (exact for every component type).
double read_component(const unsigned char* p, int type, bool normalized) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const double c = static_cast<int8_t>(p[0]);
      return normalized ? std::max(c / 127.0, -1.0) : c;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return normalized ? p[0] / 255.0 : p[0];
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : double(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : double(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default:
      return 0;
  }
}

// A run of `count` elements of `element_size` bytes, `stride` apart, inside a bufferView:
// the checked pointer to the first, or an error naming what overflows.
Status locate(const tinygltf::Model& model, int view_index, uint64_t offset, uint64_t count,
              uint64_t element_size, uint64_t stride, const std::string& what,
              const unsigned char*& first) {
  first = nullptr;
  if (view_index < 0 || static_cast<std::size_t>(view_index) >= model.bufferViews.size())
    return parse_error(what + ": bufferView " + std::to_string(view_index) + " does not exist");
  const tinygltf::BufferView& view = model.bufferViews[view_index];
  if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size())
    return parse_error(what + ": bufferView " + std::to_string(view_index) + " names buffer " +
                       std::to_string(view.buffer) + ", which does not exist");
  const std::vector<unsigned char>& buffer = model.buffers[view.buffer].data;
  if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
    return parse_error(what + ": bufferView " + std::to_string(view_index) + " (" +
                       std::to_string(view.byteLength) + " bytes at " +
                       std::to_string(view.byteOffset) + ") ends past its buffer (" +
                       std::to_string(buffer.size()) + " bytes)");
  if (count == 0) return Status::ok();
  // The last element ends at offset + (count - 1) * stride + element_size; count is first
  // bounded by the view's length so that the product cannot overflow.
  const uint64_t length = view.byteLength;
  if (offset > length || count - 1 > length / std::max<uint64_t>(stride, 1) ||
      offset + (count - 1) * stride + element_size > length)
    return parse_error(what + ": " + std::to_string(count) + " elements of " +
                       std::to_string(element_size) + " bytes, " + std::to_string(stride) +
                       " apart, from byte " + std::to_string(offset) + " end past bufferView " +
                       std::to_string(view_index) + " (" + std::to_string(length) + " bytes)");
  first = buffer.data() + view.byteOffset + offset;
  return Status::ok();
}

struct AccessorShape {
  int components = 0;
  std::size_t count = 0;
};

// Every element of accessor `index`, components back to back, as doubles; sparse
// substitution applied (§3.6.2.3). `allowed_types` lists the accepted TINYGLTF_TYPE_ values.
Status decode_accessor(const tinygltf::Model& model, int index, const std::vector<int>& allowed_types,
                       std::size_t max_elements, const std::string& what, AccessorShape& shape,
                       std::vector<double>& values) {
  if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size())
    return parse_error(what + ": accessor " + std::to_string(index) + " does not exist");
  const tinygltf::Accessor& accessor = model.accessors[index];
  const std::string name = what + ": accessor " + std::to_string(index);
  const int size = component_size(accessor.componentType);
  const int components = components_of(accessor.type);
  if (size == 0) return parse_error(name + ": unknown componentType " + std::to_string(accessor.componentType));
  if (std::find(allowed_types.begin(), allowed_types.end(), accessor.type) == allowed_types.end())
    return parse_error(name + ": type " + std::to_string(accessor.type) + " is not one this attribute takes");
  if (accessor.normalized && (size == 4))
    return parse_error(name + ": only byte and short components can be normalized");
  if (accessor.count > max_elements)
    return Status(ErrorCode::kResourceLimit, name + ": " + std::to_string(accessor.count) +
                                                 " elements, more than the " +
                                                 std::to_string(max_elements) + " allowed");
  shape.components = components;
  shape.count = accessor.count;
  const uint64_t element_size = uint64_t(size) * uint64_t(components);
  values.assign(accessor.count * components, 0.0);  // no bufferView: zeros (§3.6.2.3)
  if (accessor.bufferView >= 0) {
    const tinygltf::BufferView* view =
        static_cast<std::size_t>(accessor.bufferView) < model.bufferViews.size()
            ? &model.bufferViews[accessor.bufferView]
            : nullptr;
    const uint64_t stride = view && view->byteStride ? view->byteStride : element_size;
    if (stride < element_size)
      return parse_error(name + ": byteStride " + std::to_string(stride) +
                         " is shorter than an element (" + std::to_string(element_size) + " bytes)");
    const unsigned char* first = nullptr;
    if (Status s = locate(model, accessor.bufferView, accessor.byteOffset, accessor.count,
                          element_size, stride, name, first);
        !s)
      return s;
    for (std::size_t i = 0; i < accessor.count; ++i)
      for (int c = 0; c < components; ++c)
        values[i * components + c] = read_component(first + i * stride + std::size_t(c) * size,
                                                    accessor.componentType, accessor.normalized);
  }
  if (accessor.sparse.isSparse) {
    const auto& sparse = accessor.sparse;
    const std::string sparse_name = name + " (sparse)";
    if (sparse.count < 0 || static_cast<std::size_t>(sparse.count) > accessor.count)
      return parse_error(sparse_name + ": " + std::to_string(sparse.count) + " substitutions for " +
                         std::to_string(accessor.count) + " elements");
    const int index_type = sparse.indices.componentType;
    if (index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      return parse_error(sparse_name + ": indices of componentType " + std::to_string(index_type));
    if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0)
      return parse_error(sparse_name + ": negative byteOffset");
    const int index_size = component_size(index_type);
    const unsigned char* indices = nullptr;
    const unsigned char* substitutes = nullptr;
    if (Status s = locate(model, sparse.indices.bufferView, sparse.indices.byteOffset, sparse.count,
                          index_size, index_size, sparse_name + " indices", indices);
        !s)
      return s;
    if (Status s = locate(model, sparse.values.bufferView, sparse.values.byteOffset, sparse.count,
                          element_size, element_size, sparse_name + " values", substitutes);
        !s)
      return s;
    int64_t previous = -1;
    for (int k = 0; k < sparse.count; ++k) {
      const auto target = static_cast<int64_t>(read_component(indices + std::size_t(k) * index_size, index_type, false));
      // §3.6.2.3: indices strictly increasing, each naming an element.
      if (target <= previous || static_cast<uint64_t>(target) >= accessor.count)
        return parse_error(sparse_name + ": index " + std::to_string(target) + " at " + std::to_string(k) +
                           (target <= previous ? " does not increase" : " is past the elements"));
      previous = target;
      for (int c = 0; c < components; ++c)
        values[std::size_t(target) * components + c] =
            read_component(substitutes + std::size_t(k) * element_size + std::size_t(c) * size,
                           accessor.componentType, accessor.normalized);
    }
  }
  return Status::ok();
}

// ---------------------------------------------------------------------------------------
// Node transforms (§3.5.3): a matrix (column-major), or translation * rotation * scale.

using Matrix = std::array<double, 16>;  // column-major, as glTF stores it
constexpr Matrix kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

Matrix multiply(const Matrix& a, const Matrix& b) {
  Matrix m{};
  for (int column = 0; column < 4; ++column)
    for (int row = 0; row < 4; ++row) {
      double sum = 0;
      for (int k = 0; k < 4; ++k) sum += a[k * 4 + row] * b[column * 4 + k];
      m[column * 4 + row] = sum;
    }
  return m;
}

Status local_transform(const tinygltf::Node& node, int index, Matrix& m) {
  m = kIdentity;
  const std::string name = "node " + std::to_string(index);
  auto finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16 || !finite(node.matrix)) return parse_error(name + ": matrix is not 16 finite numbers");
    std::copy(node.matrix.begin(), node.matrix.end(), m.begin());
    return Status::ok();
  }
  if ((!node.translation.empty() && node.translation.size() != 3) ||
      (!node.rotation.empty() && node.rotation.size() != 4) || (!node.scale.empty() && node.scale.size() != 3) ||
      !finite(node.translation) || !finite(node.rotation) || !finite(node.scale))
    return parse_error(name + ": translation, rotation or scale is not 3, 4 or 3 finite numbers");
  double x = 0, y = 0, z = 0, w = 1;
  if (!node.rotation.empty()) {
    x = node.rotation[0], y = node.rotation[1], z = node.rotation[2], w = node.rotation[3];
    const double length = std::sqrt(x * x + y * y + z * z + w * w);
    if (!(length > 0)) return parse_error(name + ": rotation is a zero quaternion");
    x /= length, y /= length, z /= length, w /= length;
  }
  const double sx = node.scale.empty() ? 1 : node.scale[0];
  const double sy = node.scale.empty() ? 1 : node.scale[1];
  const double sz = node.scale.empty() ? 1 : node.scale[2];
  // The rotation matrix of a unit quaternion, its columns scaled.
  const double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),
                       2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                       2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y)};
  const double s[3] = {sx, sy, sz};
  for (int column = 0; column < 3; ++column)
    for (int row = 0; row < 3; ++row) m[column * 4 + row] = r[column * 3 + row] * s[column];
  if (!node.translation.empty())
    for (int row = 0; row < 3; ++row) m[12 + row] = node.translation[row];
  return Status::ok();
}

// ---------------------------------------------------------------------------------------
// What the reader counts as not kept, one entry per kind, printed as "TANGENT on 2 primitives".

class NotKept {
 public:
  void add(const std::string& what, const char* unit, std::size_t n = 1) {
    auto& entry = counts_[what];
    entry.first = unit;
    entry.second += n;
  }
  void describe(std::vector<std::string>& lines) const {
    for (const auto& [what, entry] : counts_)
      lines.push_back(what + " on " + std::to_string(entry.second) + " " + entry.first +
                      (entry.second == 1 ? "" : "s"));
  }

 private:
  std::map<std::string, std::pair<const char*, std::size_t>> counts_;
};

// Extensions whose absence changes no vertex and no face: a loader without them draws the
// same triangles (material and texture extensions, and the quantized accessors read here).
bool changes_no_geometry(const std::string& extension) {
  return extension == "KHR_mesh_quantization" || extension.rfind("KHR_materials_", 0) == 0 ||
         extension.rfind("KHR_texture_", 0) == 0 || extension == "EXT_texture_webp" ||
         extension == "MSFT_texture_dds" || extension == "MSFT_lod";
}

// The first of `required` (a file's extensionsRequired) that pm cannot read without, as the
// error that names it; ok when there is none.
Status unsupported_required_extension(const std::vector<std::string>& required) {
  for (const std::string& extension : required)
    if (!changes_no_geometry(extension))
      return Status(ErrorCode::kUnsupportedFormat,
                    "required extension " + extension + " is not supported (" +
                        (extension == "KHR_draco_mesh_compression" || extension == "EXT_meshopt_compression"
                             ? "compressed geometry pm does not decode"
                             : "reading without it could change the geometry") +
                        ")");
  return Status::ok();
}

// A file of another major version than 2 (glTF 1.0 from 2015: its meshes, accessors and
// scenes are laid out otherwise, so read as 2.0 it would hold no triangles, or fail
// tinygltf's checks): refused by name. `version` is asset.version as the file writes it.
Status unsupported_version(const std::string& version) {
  if (version.rfind("2.", 0) == 0) return Status::ok();
  return Status(ErrorCode::kUnsupportedFormat,
                "glTF " + (version.empty() ? std::string("without asset.version") : "version " + version) +
                    " is not supported (pm reads glTF 2.0)");
}

// Why tinygltf refused a document, when the reason is one pm names better than its parser
// does: another glTF version, an asset without its required version (tinygltf says "asset
// object not found" of an asset that is there), or a required extension pm does not read
// (Draco's accessors have no bufferView, which tinygltf reports as invalid). Ok when none
// applies.
Status unsupported_document(std::string_view json_text) {
  const nlohmann::json document = nlohmann::json::parse(json_text.begin(), json_text.end(), nullptr, false);
  if (!document.is_object()) return Status::ok();
  const auto asset = document.find("asset");
  if (asset != document.end() && asset->is_object()) {
    const auto version = asset->find("version");
    if (version == asset->end())  // §3.2: asset.version is required
      return Status(ErrorCode::kParseError, "asset.version is missing (glTF 2.0 requires it)");
    if (version->is_string() || version->is_number())
      if (Status s = unsupported_version(version->is_string() ? version->get<std::string>() : version->dump()); !s)
        return s;
  }
  const auto required = document.find("extensionsRequired");
  if (required == document.end() || !required->is_array()) return Status::ok();
  std::vector<std::string> names;
  for (const nlohmann::json& name : *required)
    if (name.is_string()) names.push_back(name.get<std::string>());
  return unsupported_required_extension(names);
}

// One mesh instance: a node's mesh and the node's world transform.
struct Instance {
  int node = -1;  // -1: a mesh read without nodes
  int mesh = 0;
  Matrix world = kIdentity;
  bool skinned = false;
};

// The instances of the default scene (§3.5.1; scene 0 when none is named; every root node
// when the file has no scenes; every mesh once when it has no nodes either), depth first,
// refusing a node met twice (a cycle, or a node with two parents: §3.5.2 forbids both).
Status collect_instances(const tinygltf::Model& model, NotKept& not_kept, std::vector<Instance>& instances) {
  std::vector<int> roots;
  if (!model.scenes.empty()) {
    const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (static_cast<std::size_t>(scene) >= model.scenes.size())
      return parse_error("scene " + std::to_string(scene) + " does not exist");
    roots = model.scenes[scene].nodes;
    if (model.scenes.size() > 1) not_kept.add("scenes other than the default", "file", model.scenes.size() - 1);
  } else if (!model.nodes.empty()) {
    std::vector<char> is_child(model.nodes.size(), 0);
    for (const tinygltf::Node& node : model.nodes)
      for (int child : node.children)
        if (child >= 0 && static_cast<std::size_t>(child) < is_child.size()) is_child[child] = 1;
    for (std::size_t i = 0; i < model.nodes.size(); ++i)
      if (!is_child[i]) roots.push_back(static_cast<int>(i));
  } else {
    for (std::size_t i = 0; i < model.meshes.size(); ++i) instances.push_back({-1, static_cast<int>(i), kIdentity, false});
    return Status::ok();
  }
  std::vector<char> visited(model.nodes.size(), 0);
  std::vector<std::pair<int, Matrix>> stack;
  for (auto root = roots.rbegin(); root != roots.rend(); ++root) stack.push_back({*root, kIdentity});
  while (!stack.empty()) {
    const auto [index, parent] = stack.back();
    stack.pop_back();
    if (index < 0 || static_cast<std::size_t>(index) >= model.nodes.size())
      return parse_error("node " + std::to_string(index) + " does not exist");
    if (visited[index])
      return parse_error("node " + std::to_string(index) +
                         " is met twice in the scene (a cycle, or two parents)");
    visited[index] = 1;
    const tinygltf::Node& node = model.nodes[index];
    Matrix local;
    if (Status s = local_transform(node, index, local); !s) return s;
    const Matrix world = multiply(parent, local);
    if (node.mesh >= 0) {
      if (static_cast<std::size_t>(node.mesh) >= model.meshes.size())
        return parse_error("node " + std::to_string(index) + ": mesh " + std::to_string(node.mesh) + " does not exist");
      instances.push_back({index, node.mesh, world, node.skin >= 0});
    }
    for (auto child = node.children.rbegin(); child != node.children.rend(); ++child)
      stack.push_back({*child, world});
  }
  return Status::ok();
}

// ---------------------------------------------------------------------------------------
// Building the mesh.

// Bit patterns as hash keys: equal floats with different bits (0 and -0) stay apart, so
// that what is written back is what was read.
struct BitsHash {
  template <std::size_t N>
  std::size_t operator()(const std::array<uint32_t, N>& key) const {
    uint64_t h = 0x9E3779B97F4A7C15ull;
    for (uint32_t k : key) h = (h ^ k) * 0x100000001B3ull + (h >> 29);
    return static_cast<std::size_t>(h);
  }
};

uint32_t bits_of(float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, 4);
  return bits;
}

// Indices into a value table, equal values (bit for bit) sharing one entry.
template <std::size_t N>
class ValueTable {
 public:
  explicit ValueTable(std::vector<float>& values) : values_(values) {}
  uint32_t add(const float* value) {
    std::array<uint32_t, N> key;
    for (std::size_t i = 0; i < N; ++i) key[i] = bits_of(value[i]);
    auto [it, inserted] = ids_.try_emplace(key, static_cast<uint32_t>(values_.size() / N));
    if (inserted) values_.insert(values_.end(), value, value + N);
    return it->second;
  }

 private:
  std::vector<float>& values_;
  std::unordered_map<std::array<uint32_t, N>, uint32_t, BitsHash> ids_;
};

bool to_float(double value, float& out) {
  if (!std::isfinite(value) || std::fabs(value) > std::numeric_limits<float>::max()) return false;
  out = static_cast<float>(value);
  return true;
}

struct PrimitiveData {
  AccessorShape position_shape, normal_shape, uv_shape, color_shape;
  std::vector<double> positions, normals, uvs, colors;
  std::vector<uint32_t> triangles;  // 3 per triangle, into the primitive's vertices
};

class GltfMeshBuilder {
 public:
  GltfMeshBuilder(const tinygltf::Model& model, const GltfReadOptions& options, Mesh& mesh, ReadReport& report)
      : model_(model), options_(options), mesh_(mesh), report_(report), uv_table_(mesh.uvs),
        normal_table_(mesh.normals) {}

  Status build();

 private:
  Status check_extensions();
  Status plan(const std::vector<Instance>& instances);
  Status read_primitive(int mesh_index, int primitive_index, PrimitiveData& data);
  Status add_instance(const Instance& instance);

  const tinygltf::Model& model_;
  const GltfReadOptions& options_;
  Mesh& mesh_;
  ReadReport& report_;
  NotKept not_kept_;
  ValueTable<2> uv_table_;
  ValueTable<3> normal_table_;
  std::vector<std::string> material_names_;       // by glTF material index
  std::vector<uint32_t> material_ids_;            // glTF material -> mesh material, or kNoAttribute
  std::map<std::pair<int, int>, PrimitiveData> primitives_;  // decoded once per (mesh, primitive)
  bool any_uvs_ = false, any_normals_ = false;
};

Status GltfMeshBuilder::check_extensions() {
  if (Status s = unsupported_version(model_.asset.version); !s) return s;
  if (Status s = unsupported_required_extension(model_.extensionsRequired); !s) return s;
  for (const std::string& extension : model_.extensionsUsed)
    if (extension == "EXT_mesh_gpu_instancing")
      not_kept_.add("EXT_mesh_gpu_instancing (one instance read)", "file");
  if (!model_.animations.empty()) not_kept_.add("animations", "file", 1);
  return Status::ok();
}

// Decodes the primitives the instances use, once each, and checks the face total before
// any face is built.
Status GltfMeshBuilder::plan(const std::vector<Instance>& instances) {
  uint64_t faces = 0;
  for (const Instance& instance : instances) {
    const tinygltf::Mesh& mesh = model_.meshes[instance.mesh];
    const std::vector<double>& weights = instance.node >= 0 && !model_.nodes[instance.node].weights.empty()
                                             ? model_.nodes[instance.node].weights
                                             : mesh.weights;
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const tinygltf::Primitive& primitive = mesh.primitives[p];
      const std::string name = "mesh " + std::to_string(instance.mesh) + " primitive " + std::to_string(p);
      if (primitive.extensions.count("KHR_draco_mesh_compression"))
        return Status(ErrorCode::kUnsupportedFormat,
                      name + " is Draco-compressed (KHR_draco_mesh_compression), which pm does not decode");
      if (!primitive.targets.empty()) {
        if (std::any_of(weights.begin(), weights.end(), [](double w) { return w != 0; }))
          return Status(ErrorCode::kUnsupportedFormat,
                        name + " has morph targets with non-zero weights: dropping them would change its shape");
        not_kept_.add("morph targets (weights 0)", "primitive");
      }
      const auto key = std::make_pair(instance.mesh, static_cast<int>(p));
      auto found = primitives_.find(key);
      if (found == primitives_.end()) {
        PrimitiveData data;
        if (Status s = read_primitive(instance.mesh, static_cast<int>(p), data); !s) return s;
        found = primitives_.emplace(key, std::move(data)).first;
      }
      faces += found->second.triangles.size() / 3;
      if (faces > options_.max_faces)
        return Status(ErrorCode::kResourceLimit, "the scene instances more than " +
                                                     std::to_string(options_.max_faces) + " faces");
      any_uvs_ |= !found->second.uvs.empty();
      any_normals_ |= !found->second.normals.empty();
      if (!found->second.colors.empty())
        mesh_.color_components = std::max<uint32_t>(mesh_.color_components, found->second.color_shape.components);
    }
    if (instance.skinned) not_kept_.add("skin (read in its bind pose)", "node");
  }
  return Status::ok();
}

Status GltfMeshBuilder::read_primitive(int mesh_index, int primitive_index, PrimitiveData& data) {
  const tinygltf::Primitive& primitive = model_.meshes[mesh_index].primitives[primitive_index];
  const std::string name = "mesh " + std::to_string(mesh_index) + " primitive " + std::to_string(primitive_index);
  const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
  if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
    if (mode < 0 || mode > TINYGLTF_MODE_TRIANGLE_FAN) return parse_error(name + ": unknown mode " + std::to_string(mode));
    not_kept_.add("points and lines (pm holds triangles)", "primitive");
    return Status::ok();
  }
  const auto position = primitive.attributes.find("POSITION");
  if (position == primitive.attributes.end()) {
    not_kept_.add("primitive without POSITION", "primitive");
    return Status::ok();
  }
  // Elements a primitive may have: at most 3 per face the limit allows (a vertex no face
  // uses is not read), and at most what a 32-bit index names.
  const std::size_t max_elements = std::min<uint64_t>(3 * uint64_t(options_.max_faces), UINT32_MAX);
  using T = std::vector<int>;
  if (Status s = decode_accessor(model_, position->second, T{TINYGLTF_TYPE_VEC3}, max_elements, name + " POSITION",
                                 data.position_shape, data.positions);
      !s)
    return s;
  const std::size_t vertices = data.position_shape.count;
  for (const auto& [attribute, accessor] : primitive.attributes) {
    std::vector<double>* values = nullptr;
    AccessorShape* shape = nullptr;
    T types = {TINYGLTF_TYPE_VEC3};
    if (attribute == "NORMAL") {
      values = &data.normals, shape = &data.normal_shape;
    } else if (attribute == "TEXCOORD_0") {
      values = &data.uvs, shape = &data.uv_shape, types = {TINYGLTF_TYPE_VEC2};
    } else if (attribute == "COLOR_0") {
      values = &data.colors, shape = &data.color_shape, types = {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4};
    } else {
      if (attribute != "POSITION") not_kept_.add(attribute, "primitive");
      continue;
    }
    if (Status s = decode_accessor(model_, accessor, types, max_elements, name + " " + attribute, *shape, *values); !s)
      return s;
    if (shape->count != vertices)
      return parse_error(name + ": " + attribute + " has " + std::to_string(shape->count) + " elements, POSITION " +
                         std::to_string(vertices));
  }
  for (double v : data.positions)
    if (!std::isfinite(v)) return parse_error(name + ": non-finite POSITION");
  for (const std::vector<double>* values : {&data.normals, &data.uvs, &data.colors})
    for (double v : *values)
      if (!std::isfinite(v)) return parse_error(name + ": non-finite attribute value");

  std::vector<uint32_t> indices;
  if (primitive.indices >= 0) {
    AccessorShape shape;
    std::vector<double> values;
    if (Status s = decode_accessor(model_, primitive.indices, T{TINYGLTF_TYPE_SCALAR}, max_elements, name + " indices",
                                   shape, values);
        !s)
      return s;
    const int type = model_.accessors[primitive.indices].componentType;
    if (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      return parse_error(name + ": indices of componentType " + std::to_string(type) + " (unsigned integers only)");
    indices.resize(values.size());
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (!(values[i] < double(vertices)))
        return parse_error(name + ": index " + std::to_string(i) + " is vertex " +
                           std::to_string(static_cast<uint64_t>(values[i])) + " of " + std::to_string(vertices));
      indices[i] = static_cast<uint32_t>(values[i]);
    }
  } else {
    indices.resize(vertices);
    for (std::size_t i = 0; i < vertices; ++i) indices[i] = static_cast<uint32_t>(i);
  }
  // §3.7.2.1: strips and fans as triangles, every other strip triangle turned back over.
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    if (indices.size() % 3) not_kept_.add("indices after the last whole triangle", "primitive");
    data.triangles.assign(indices.begin(), indices.end() - indices.size() % 3);
  } else {
    for (std::size_t i = 2; i < indices.size(); ++i) {
      if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
        data.triangles.insert(data.triangles.end(), {indices[0], indices[i - 1], indices[i]});
      } else if (i % 2 == 0) {
        data.triangles.insert(data.triangles.end(), {indices[i - 2], indices[i - 1], indices[i]});
      } else {
        data.triangles.insert(data.triangles.end(), {indices[i - 1], indices[i - 2], indices[i]});
      }
    }
    ++report_.polygons_triangulated;
  }
  return Status::ok();
}

// Appends one instance's triangles in world space (positions through the world matrix,
// normals through its inverse transpose), welding its equal vertices.
Status GltfMeshBuilder::add_instance(const Instance& instance) {
  const Matrix& m = instance.skinned ? kIdentity : instance.world;  // §3.7.3: a skinned mesh ignores its node
  const bool identity = m == kIdentity;
  // The normal matrix: the cofactors of the upper 3x3 (its inverse transpose times the
  // determinant), with the determinant's sign, so that a mirror keeps normals outward.
  const double a = m[0], b = m[4], c = m[8], d = m[1], e = m[5], f = m[9], g = m[2], h = m[6], k = m[10];
  const double cof[9] = {e * k - f * h, -(d * k - f * g), d * h - e * g, -(b * k - c * h), a * k - c * g,
                         -(a * h - b * g), b * f - c * e,   -(a * f - c * d), a * e - b * d};
  const double determinant = a * cof[0] + b * cof[1] + c * cof[2];
  const bool mirrored = determinant < 0;
  const double sign = mirrored ? -1 : 1;
  std::unordered_map<std::array<uint32_t, 7>, uint32_t, BitsHash> welded;
  const tinygltf::Mesh& gltf_mesh = model_.meshes[instance.mesh];
  for (std::size_t p = 0; p < gltf_mesh.primitives.size(); ++p) {
    const PrimitiveData& data = primitives_.at({instance.mesh, static_cast<int>(p)});
    if (data.triangles.empty()) continue;
    const std::string name = "node " + std::to_string(instance.node) + " mesh " + std::to_string(instance.mesh) +
                             " primitive " + std::to_string(p);
    // This primitive's vertices in the merged mesh, made when a face first uses them.
    std::vector<uint32_t> vertex_of(data.position_shape.count, kNoAttribute);
    std::vector<uint32_t> uv_of, normal_of;
    const int material = gltf_mesh.primitives[p].material;
    uint32_t material_id = kNoAttribute;
    if (material >= 0) {
      if (static_cast<std::size_t>(material) >= model_.materials.size())
        return parse_error(name + ": material " + std::to_string(material) + " does not exist");
      if (material_ids_[material] == kNoAttribute) {
        material_ids_[material] = static_cast<uint32_t>(mesh_.material_names.size());
        mesh_.material_names.push_back(material_names_[material]);
      }
      material_id = material_ids_[material];
    }
    const uint32_t components = mesh_.color_components;
    auto vertex = [&](uint32_t v) -> Status {
      if (vertex_of[v] != kNoAttribute) return Status::ok();
      float xyz[3];
      for (int r = 0; r < 3; ++r) {
        const double* q = &data.positions[3 * std::size_t{v}];
        if (identity) {
          xyz[r] = static_cast<float>(q[r]);
        } else if (!to_float(m[r] * q[0] + m[4 + r] * q[1] + m[8 + r] * q[2] + m[12 + r], xyz[r])) {
          return parse_error(name + ": vertex " + std::to_string(v) + " is out of float range in world space");
        }
      }
      std::array<float, 4> rgba = {1, 1, 1, 1};
      if (!data.colors.empty()) {
        const int n = data.color_shape.components;
        for (int i = 0; i < n; ++i) rgba[i] = static_cast<float>(data.colors[std::size_t{v} * n + i]);
      } else if (components) {
        ++report_.vertices_given_default_color;
      }
      std::array<uint32_t, 7> key = {bits_of(xyz[0]), bits_of(xyz[1]), bits_of(xyz[2]), 0, 0, 0, 0};
      for (uint32_t i = 0; i < components; ++i) key[3 + i] = bits_of(rgba[i]);
      auto [it, inserted] = welded.try_emplace(key, static_cast<uint32_t>(mesh_.vertex_count()));
      if (inserted) {
        mesh_.positions.insert(mesh_.positions.end(), xyz, xyz + 3);
        mesh_.colors.insert(mesh_.colors.end(), rgba.begin(), rgba.begin() + components);
      }
      vertex_of[v] = it->second;
      return Status::ok();
    };
    auto uv = [&](uint32_t v) -> uint32_t {
      if (data.uvs.empty()) return kNoAttribute;
      if (uv_of.empty()) uv_of.assign(data.uv_shape.count, kNoAttribute);
      if (uv_of[v] == kNoAttribute) {
        const float value[2] = {static_cast<float>(data.uvs[2 * std::size_t{v}]),
                                static_cast<float>(data.uvs[2 * std::size_t{v} + 1])};
        uv_of[v] = uv_table_.add(value);
      }
      return uv_of[v];
    };
    auto normal = [&](uint32_t v) -> uint32_t {
      if (data.normals.empty()) return kNoAttribute;
      if (normal_of.empty()) normal_of.assign(data.normal_shape.count, kNoAttribute);
      if (normal_of[v] == kNoAttribute) {
        const double* n = &data.normals[3 * std::size_t{v}];
        float value[3];
        if (identity) {
          for (int r = 0; r < 3; ++r) value[r] = static_cast<float>(n[r]);
        } else {
          double t[3];
          for (int r = 0; r < 3; ++r) t[r] = sign * (cof[r] * n[0] + cof[3 + r] * n[1] + cof[6 + r] * n[2]);
          const double length = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
          for (int r = 0; r < 3; ++r) value[r] = static_cast<float>(length > 0 ? t[r] / length : 0.0);
        }
        normal_of[v] = normal_table_.add(value);
      }
      return normal_of[v];
    };
    for (std::size_t t = 0; t < data.triangles.size(); t += 3) {
      uint32_t corners[3] = {data.triangles[t], data.triangles[t + 1], data.triangles[t + 2]};
      if (mirrored) std::swap(corners[1], corners[2]);  // §3.7.4: the determinant's sign sets the winding
      for (uint32_t v : corners) {
        if (Status s = vertex(v); !s) return s;
        mesh_.triangles.push_back(vertex_of[v]);
        if (any_uvs_) mesh_.uv_indices.push_back(uv(v));
        if (any_normals_) mesh_.normal_indices.push_back(normal(v));
      }
      if (!material_ids_.empty()) mesh_.face_materials.push_back(material_id);
    }
  }
  return Status::ok();
}

Status GltfMeshBuilder::build() {
  if (Status s = check_extensions(); !s) return s;
  std::vector<Instance> instances;
  if (Status s = collect_instances(model_, not_kept_, instances); !s) return s;
  std::vector<std::string> raw;
  for (const tinygltf::Material& material : model_.materials) raw.push_back(material.name);
  material_names_ = detail::unique_material_names(raw);
  material_ids_.assign(model_.materials.size(), kNoAttribute);
  if (Status s = plan(instances); !s) return s;
  for (const Instance& instance : instances)
    if (Status s = add_instance(instance); !s) return s;
  // Faces of materials only: faces without one have none; no material used, no table.
  if (mesh_.material_names.empty()) mesh_.face_materials.clear();
  not_kept_.describe(report_.ignored_properties);
  if (mesh_.face_count() == 0) {
    // What the scene held instead, when anything (points and lines, a primitive without
    // positions): the reason a user looks for.
    std::string held;
    for (const std::string& line : report_.ignored_properties) held += (held.empty() ? "" : "; ") + line;
    return Status(ErrorCode::kEmptyMesh,
                  "no triangles in the default scene" + (held.empty() ? "" : " (it holds " + held + ")"));
  }
  if (mesh_.face_count() >= (std::size_t{1} << 30) || mesh_.vertex_count() >= (std::size_t{1} << 30))
    return Status(ErrorCode::kResourceLimit, "more than 2^30 faces or vertices");
  return Status::ok();
}

// tinygltf's file access, limited to what a reader of geometry needs: external buffers
// beside the file, no shell expansion of their names.
bool file_exists(const std::string& path, void*) {
  std::error_code error;
  return std::filesystem::is_regular_file(path, error);
}
std::string expand_path(const std::string& path, void*) { return path; }
bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    if (err) *err += "cannot open " + path;
    return false;
  }
  out->assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  return true;
}
bool refuse_file(std::vector<unsigned char>*, std::string* err, const std::string& path, void*) {
  if (err) *err += "buffer '" + path + "' is another file, and the glTF was read from memory";
  return false;
}
bool no_writes(std::string*, const std::string&, const std::vector<unsigned char>&, void*) { return false; }
// Images are kept by reference, never decoded.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

// tinygltf's error text as one line.
std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text.empty() ? "malformed glTF" : text;
}

}  // namespace

Status read_gltf(std::string_view bytes, const GltfReadOptions& options, Mesh& mesh, ReadReport* report) {
  try {
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&skip_image, nullptr);
    const bool from_memory = options.base_directory.empty();
    loader.SetFsCallbacks({&file_exists, &expand_path, from_memory ? &refuse_file : &read_whole_file, &no_writes, nullptr});
    tinygltf::Model model;
    std::string error, warning;
    bool loaded = false;
    std::string_view json_text = bytes;  // the document, for a refusal's reason
    if (detail::is_glb(bytes)) {
      detail::GlbChunks chunks;
      if (Status s = detail::split_glb(bytes, chunks); !s) return s;
      json_text = chunks.json;
      // tinygltf is given a GLB rebuilt to the letter of §4.4 (padded chunks, BIN second): it
      // trusts lengths that split_glb has just checked.
      const std::string glb = detail::make_glb(chunks.json, chunks.binary);
      if (glb.size() > UINT32_MAX) return Status(ErrorCode::kResourceLimit, "glb of 4 GB or more");
      loaded = loader.LoadBinaryFromMemory(&model, &error, &warning, reinterpret_cast<const unsigned char*>(glb.data()),
                                           static_cast<unsigned>(glb.size()), options.base_directory);
    } else {
      if (bytes.empty()) return Status(ErrorCode::kEmptyMesh, "empty file");
      if (bytes.size() > UINT32_MAX) return Status(ErrorCode::kResourceLimit, "gltf of 4 GB or more");
      loaded = loader.LoadASCIIFromString(&model, &error, &warning, bytes.data(), static_cast<unsigned>(bytes.size()),
                                          options.base_directory);
    }
    if (!loaded) {
      if (Status s = unsupported_document(json_text); !s) return s;
      return parse_error(one_line(error));
    }
    Mesh built;
    ReadReport built_report;
    GltfMeshBuilder builder(model, options, built, built_report);
    if (Status s = builder.build(); !s) return s;
    mesh = std::move(built);
    if (report) *report = std::move(built_report);
    return Status::ok();
  } catch (const std::bad_alloc&) {
    return Status(ErrorCode::kResourceLimit, "out of memory reading the glTF");
  } catch (const std::exception& e) {
    // tinygltf and its JSON parser throw on some malformed input (a zero-length buffer, a
    // value of the wrong JSON type).
    return parse_error(std::string("malformed glTF (") + e.what() + ")");
  }
}

std::vector<std::string> gltf_material_names(std::string_view bytes) {
  std::string_view json = bytes;
  detail::GlbChunks chunks;
  if (detail::is_glb(bytes)) {
    if (!detail::split_glb(bytes, chunks)) return {};
    json = chunks.json;
  }
  const nlohmann::json document = nlohmann::json::parse(json.begin(), json.end(), nullptr, false);
  if (!document.is_object() || !document.contains("materials") || !document["materials"].is_array()) return {};
  std::vector<std::string> raw;
  for (const nlohmann::json& material : document["materials"])
    raw.push_back(material.is_object() && material.contains("name") && material["name"].is_string()
                      ? material["name"].get<std::string>()
                      : std::string());
  return detail::unique_material_names(raw);
}

}  // namespace pm
