// Reading and writing meshes: OBJ (own parser), PLY, OFF and STL (read through
// OpenMesh's IO readers into a raw importer, so no face or vertex is merged or dropped).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "pm/mesh.h"
#include "pm/status.h"

namespace pm {

enum class MeshFormat { kUnknown, kObj, kPly, kOff, kStl };

// By the file name's extension, case-insensitive (".obj", ".PLY", ...).
MeshFormat mesh_format_from_path(std::string_view path);
const char* mesh_format_name(MeshFormat format);  // "obj", "ply", "off", "stl", "unknown"

// What a reader did to the data beyond copying it; the CLI reports it on stderr.
struct ReadReport {
  std::size_t polygons_triangulated = 0;  // faces of 4+ corners split into a fan
  std::size_t ignored_lines = 0;          // OBJ lines of kinds we do not use (l, p, vp, ...)
};

// Reads a whole file. Errors: kIoError (cannot open/read), kParseError (malformed:
// the message names the line or element), kUnsupportedFormat (extension).
// A mesh with neither vertices nor faces is kEmptyMesh.
Status read_mesh(const std::string& path, Mesh& mesh, ReadReport* report = nullptr);

// Parses a mesh held in memory (stdin, tests).
Status read_mesh_from_memory(std::string_view bytes, MeshFormat format, Mesh& mesh,
                             ReadReport* report = nullptr);

// Serializes a mesh: OBJ as text with float32 positions printed in their shortest form
// that reads back to the same bits; PLY binary little-endian; OFF text; STL binary.
Status write_mesh_to_memory(const Mesh& mesh, MeshFormat format, std::string& bytes);

}  // namespace pm
