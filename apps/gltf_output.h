// pmdec's glTF output (pm/gltf.h): one level, or a whole --lods chain in one file, with
// --quantize (KHR_mesh_quantization) and --material-from SOURCE (the source's material
// definitions, its relative image URIs made relative to each output's directory).
#pragma once

#include <string>
#include <vector>

#include "pm/gltf.h"
#include "pm/mesh_io.h"
#include "pm/status.h"

namespace pm::cli {

bool is_gltf(MeshFormat format);

struct GltfOutputOptions {
  bool quantize = false;
  std::string material_source_path;  // --material-from, or empty
  std::string material_source;       // its bytes, read once before any work
};

// Reads --material-from's file into options (kIoError when it cannot be read; its contents
// are checked when a level is written).
Status load_material_source(GltfOutputOptions& options);

// `levels` coarse to fine, serialized for `output` (kGlb or kGltf).
Status encode_gltf_output(const std::vector<GltfLevel>& levels, MeshFormat format, const std::string& output,
                          const GltfOutputOptions& options, std::string& bytes);

}  // namespace pm::cli
