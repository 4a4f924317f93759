// glTF 2.0 in and out (glTF 2.0 specification, Khronos 2017/2021). Reading merges the default
// scene into one Mesh; writing gives one level as a plain mesh, or a whole chain of levels in
// ONE file: one vertex buffer in the order the levels first use their vertices (coarse to
// fine, so that each level uses a prefix of it), one index accessor per level and material,
// the levels tied together by MSFT_lod. README.md, "glTF", says what is kept and how.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "pm/mesh.h"
#include "pm/mesh_io.h"
#include "pm/status.h"

namespace pm {

struct GltfReadOptions {
  // Where the external buffers of a .gltf (uri "mesh.bin") are looked for: the directory of
  // the file. Empty: a buffer in another file is refused (bytes in memory have no directory).
  std::string base_directory;
  // A scene that instances more faces than this (all nodes together) is refused with
  // kResourceLimit before it is built.
  std::size_t max_faces = std::size_t{1} << 30;
};

// Reads a .glb (told by its magic "glTF") or a .gltf: every triangle primitive of every mesh
// instance of the default scene (scene 0 without one; every root node without scenes), node
// transforms applied (a mirroring one turns its triangles over), merged into one mesh:
//  * vertices of one node's mesh with the same world position (bit for bit) and colour are
//    one vertex: a glTF vertex split for a UV seam or a crease becomes one vertex with
//    several wedges, as the .pm holds them (Hoppe 1996, §3);
//  * TEXCOORD_0 and NORMAL per corner (tables without repeats), COLOR_0 per vertex (white
//    where a primitive has none, counted), each primitive's material as a material named as
//    gltf_material_names() says;
//  * integer and normalized accessors (KHR_mesh_quantization included), sparse accessors and
//    strides decoded; triangle strips and fans split into triangles (counted as polygons).
// What a Mesh cannot hold is counted in report->ignored_properties ("TANGENT on 2
// primitives", "skin on 1 node (read in its bind pose)", ...), never dropped silently, and
// refused where dropping it would change the geometry (kUnsupportedFormat, naming it): a
// Draco-compressed primitive, morph targets with non-zero weights, a required extension pm
// does not know, a glTF version other than 2 (asset.version). Malformed files (bad JSON, GLB chunks past the end, accessors or strides
// past their buffers, indices out of range) are kParseError, too many faces kResourceLimit,
// no triangle kEmptyMesh.
[[nodiscard]] Status read_gltf(std::string_view bytes, const GltfReadOptions& options, Mesh& mesh,
                 ReadReport* report = nullptr);

// The material names read_gltf gives a file's materials, by index: the material's own name,
// or "material_N" (N its index) when it has none, repeats an earlier one or would not read
// back from an OBJ (control characters, '#', blanks at an end).
std::vector<std::string> gltf_material_names(std::string_view bytes);

// A glTF file whose material definitions (and their textures, samplers and images) the
// writer copies for the materials it names (pmdec --material-from IN.gltf).
struct GltfMaterialSource {
  std::string bytes;  // the .gltf or .glb, as read
  // Prepended to its relative image URIs: where its directory is, seen from the output's.
  std::string image_directory;
};

struct GltfWriteOptions {
  bool binary = true;  // .glb; false: .gltf, its buffer inline as a base64 data URI
  // KHR_mesh_quantization (listed in extensionsRequired): positions as 16-bit integers on a
  // grid that the node's translation and scale map back, normals as 8-bit and texture
  // coordinates in [0, 1] as 16-bit normalized integers.
  bool quantize = false;
  const GltfMaterialSource* materials = nullptr;  // null: materials by name only
};

// One level of a chain: its mesh and its error bound (model units), from which the
// MSFT_screencoverage hints are made.
struct GltfLevel {
  const Mesh* mesh = nullptr;
  double error = 0;
};

// Serializes `levels`, coarse to fine. One level: a node with a mesh. Several: one node per
// level, the finest in the scene with MSFT_lod naming the coarser ones (a loader without
// the extension shows the finest), all sharing one vertex buffer and its accessors. Each
// level is one mesh with one primitive per material (faces without a material in one of
// their own). Errors: kInvalidArgument for no level, a mesh that fails validate_attributes
// or has non-finite values, a material source that does not parse (kParseError).
[[nodiscard]] Status write_gltf(const std::vector<GltfLevel>& levels, const GltfWriteOptions& options,
                  std::string& bytes);

}  // namespace pm
