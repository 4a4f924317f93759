// Reading and writing meshes with their attributes (mesh.h): OBJ, PLY and OFF (own parsers),
// STL (read through OpenMesh's STL reader; it has no attributes), glTF 2.0 (.gltf and .glb:
// pm/gltf.h, which also writes chains of levels). What each format carries
// and how it is written is in README.md, "Input and output formats".
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "pm/mesh.h"
#include "pm/status.h"

namespace pm {

enum class MeshFormat { kUnknown, kObj, kPly, kOff, kStl, kGltf, kGlb };

// By the file name's extension, case-insensitive (".obj", ".PLY", ...).
MeshFormat mesh_format_from_path(std::string_view path);
// "obj", "ply", "off", "stl", "gltf", "glb", "unknown"
const char* mesh_format_name(MeshFormat format);

// What a reader did to the data beyond copying it; the CLI reports it on stderr. Nothing a
// reader cannot keep is dropped without being counted here.
struct ReadReport {
  std::size_t polygons_triangulated = 0;  // faces of 4+ corners split into a fan
  std::size_t ignored_lines = 0;          // OBJ lines of kinds we do not use (l, p, vp, ...)
  // OBJ `v x y z w` with w != 1: the weight of rational curves and surfaces (Wavefront OBJ,
  // Appendix B1, "v"); a polygon mesh has no use for it and it is not kept.
  std::size_t vertex_weights_dropped = 0;
  // OBJ `vt u v w` with w != 0: the depth of a 3D texture coordinate is not kept.
  std::size_t texture_depths_dropped = 0;
  // OBJ files where only some vertices have a colour (`v x y z r g b`): the others are given
  // opaque white (1 1 1, alpha 1), which is what a renderer multiplies by for "no colour".
  std::size_t vertices_given_default_color = 0;
  // PLY properties and elements, OFF per-face colours, that were read but not kept, once
  // each, e.g. "vertex.quality", "face.red", "element edge", "off face colours".
  std::vector<std::string> ignored_properties;
};

// One line per non-zero entry of the report, for a tool to print: "3 polygons were split
// into triangles", "ignored ply property vertex.quality", ...
std::vector<std::string> describe_read_report(const ReadReport& report);

// Reads a whole file (a .gltf's external buffers from its directory). Errors: kIoError
// (cannot open/read), kParseError (malformed: the message names the line or element),
// kUnsupportedFormat (extension; for glTF also what read_gltf refuses).
// A mesh with neither vertices nor faces is kEmptyMesh.
[[nodiscard]] Status read_mesh(const std::string& path, Mesh& mesh, ReadReport* report = nullptr);

// Parses a mesh held in memory (stdin, tests); a .gltf whose buffers are other files is
// refused (bytes in memory have no directory).
[[nodiscard]] Status read_mesh_from_memory(std::string_view bytes, MeshFormat format, Mesh& mesh,
                             ReadReport* report = nullptr);

// Serializes a mesh with every attribute the format can hold (README.md, "Input and output
// formats"): OBJ and OFF as text with float32 values printed in their shortest form that
// reads back to the same bits; PLY binary little-endian; STL binary (geometry only). Read
// back, every face's corner values are the same bits (OFF keeps no materials and writes a
// vertex once per distinct texture coordinate and normal at its corners). Errors:
// kInvalidArgument for a mesh that fails validate_attributes, has non-finite values or a
// material name that would not read back as itself (empty, control characters, blanks at
// an end or in a library name, a '#' starting a comment).
[[nodiscard]] Status write_mesh_to_memory(const Mesh& mesh, MeshFormat format, std::string& bytes);

// Where write_mesh_to_sink() puts a mesh's serialization: called with its consecutive pieces,
// in order, none empty, each a megabyte or so, viewing the writer's own buffer, valid only
// during the call (copy what you keep). A sink that cannot take a piece returns the Status to
// stop with (e.g. kIoError naming its file): the writer calls it no more and returns that
// Status as it is. An exception out of the sink is kInternal (std::bad_alloc:
// kResourceLimit), as if it had returned one.
using MeshByteSink = std::function<Status(std::string_view piece)>;

// write_mesh_to_memory(), given to `sink` piece by piece as it is made, so that the whole
// text of a large mesh is never in memory (pmdec writes its outputs so): the same bytes and
// the same errors. Every error of the mesh itself (what write_mesh_to_memory() refuses) comes
// before the first piece, so the sink sees nothing of a mesh that cannot be written; after a
// sink's error, what it was given is incomplete, for the caller to throw away. glTF is made
// whole first (its JSON names its buffer's length), then given out in pieces. An empty
// `sink` is kInvalidArgument.
[[nodiscard]] Status write_mesh_to_sink(const Mesh& mesh, MeshFormat format,
                                        const MeshByteSink& sink);

}  // namespace pm
