// encode() on views (mesh_view.h): the rows gathered into the Mesh the encoder reads.
#include "pm/mesh_view.h"

#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "core/no_throw.h"

namespace pm {

namespace {

// Appends view's rows (width values each) to out; false when the view is malformed.
template <class T>
bool gather(const RowsView<T>& view, std::size_t width, const char* what, std::vector<T>& out,
            std::string& problem) {
  if (view.count == 0) return true;
  const std::size_t row = width * sizeof(T);
  const std::size_t stride = view.stride == 0 ? row : view.stride;
  if (view.data == nullptr || stride < row) {
    problem = std::string(what) + (view.data == nullptr ? ": rows without data"
                                                        : ": stride shorter than a row");
    return false;
  }
  out.resize(view.count * width);
  const char* bytes = reinterpret_cast<const char*>(view.data);
  if (stride == row) {
    std::memcpy(out.data(), bytes, view.count * row);
  } else {
    for (std::size_t i = 0; i < view.count; ++i) {
      std::memcpy(&out[i * width], bytes + i * stride, row);
    }
  }
  return true;
}

}  // namespace

Status encode(const MeshView& input, const EncodeOptions& options, ProgressiveMesh& out,
              EncodeStats* stats) {
  return encode(input, options, WriteOptions{}, out, stats);
}

Status encode(const MeshView& input, const EncodeOptions& options, const WriteOptions& stream,
              ProgressiveMesh& out, EncodeStats* stats) {
  Mesh mesh;
  std::string problem;
  const Status gathered = detail::no_throw([&] {
    if (input.color_components == 0 && input.colors.count != 0)
      return Status(ErrorCode::kInvalidArgument, "colors: rows without color_components");
    const bool ok = gather(input.positions, 3, "positions", mesh.positions, problem) &&
                    gather(input.triangles, 3, "triangles", mesh.triangles, problem) &&
                    gather(input.colors, input.color_components, "colors", mesh.colors, problem) &&
                    gather(input.uvs, 2, "uvs", mesh.uvs, problem) &&
                    gather(input.uv_indices, 3, "uv_indices", mesh.uv_indices, problem) &&
                    gather(input.normals, 3, "normals", mesh.normals, problem) &&
                    gather(input.normal_indices, 3, "normal_indices", mesh.normal_indices, problem) &&
                    gather(input.face_materials, 1, "face_materials", mesh.face_materials, problem);
    if (!ok) return Status(ErrorCode::kInvalidArgument, problem);
    mesh.color_components = input.color_components;
    if (input.material_names) mesh.material_names = *input.material_names;
    if (input.material_libraries) mesh.material_libraries = *input.material_libraries;
    return Status::ok();
  });
  if (!gathered) return gathered;
  // The gathered copy is encode()'s alone: it goes as soon as the collapse loop has its own.
  return encode(std::move(mesh), options, stream, out, stats);
}

}  // namespace pm
