#include "gltf_output.h"

#include <filesystem>

#include "cli_common.h"

namespace pm::cli {

bool is_gltf(MeshFormat format) { return format == MeshFormat::kGltf || format == MeshFormat::kGlb; }

Status load_material_source(GltfOutputOptions& options) {
  if (options.material_source_path.empty()) return Status::ok();
  return read_whole_input(options.material_source_path, options.material_source);
}

Status encode_gltf_output(const std::vector<GltfLevel>& levels, MeshFormat format, const std::string& output,
                          const GltfOutputOptions& options, std::string& bytes) {
  GltfWriteOptions write;
  write.binary = format == MeshFormat::kGlb;
  write.quantize = options.quantize;
  GltfMaterialSource source;
  if (!options.material_source_path.empty()) {
    namespace fs = std::filesystem;
    source.bytes = options.material_source;
    // The source's directory as seen from the output's: its relative image URIs stay valid.
    std::error_code error;
    const fs::path from = fs::absolute(fs::path(output).parent_path(), error);
    const fs::path to = fs::absolute(fs::path(options.material_source_path).parent_path(), error);
    const fs::path relative = to.lexically_relative(from);
    source.image_directory = relative.empty() || relative == "." ? "" : relative.generic_string();
    write.materials = &source;
  }
  return write_gltf(levels, write, bytes);
}

}  // namespace pm::cli
