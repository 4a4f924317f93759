// Format detection, file reading and dispatch to the readers, one file each: OBJ
// (obj_reader.cpp), OFF (off_reader.cpp), PLY (ply_header.cpp, ply_reader.cpp), all three
// our own parsers, with their attributes (off_reader.cpp and ply_reader.cpp say why not
// OpenMesh's); STL through OpenMesh's reader, behind checks of ours (stl_reader.cpp).

#include "pm/mesh_io.h"

#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "core/no_throw.h"
#include "io/mesh_readers.h"
#include "io/reader_support.h"
#include "pm/gltf.h"

namespace pm {

std::vector<std::string> describe_read_report(const ReadReport& report) {
  std::vector<std::string> lines;
  auto count = [&lines](std::size_t n, const char* one, const char* many) {
    if (n == 0) return;
    lines.push_back(std::to_string(n) + " " + (n == 1 ? one : many));
  };
  count(report.polygons_triangulated, "polygon was split into triangles",
        "polygons were split into triangles");
  count(report.ignored_lines, "line of an unused kind was ignored",
        "lines of unused kinds were ignored");
  count(report.vertex_weights_dropped, "vertex weight w != 1 was not kept",
        "vertex weights w != 1 were not kept");
  count(report.texture_depths_dropped, "texture coordinate w != 0 was not kept",
        "texture coordinate w values != 0 were not kept");
  count(report.vertices_given_default_color, "vertex without a colour was given white",
        "vertices without a colour were given white");
  for (const std::string& property : report.ignored_properties) {
    lines.push_back("not kept: " + property);
  }
  return lines;
}

MeshFormat mesh_format_from_path(std::string_view path) {
  const std::size_t slash = path.find_last_of("/\\");
  const std::string_view file_name =
      slash == std::string_view::npos ? path : path.substr(slash + 1);
  const std::size_t dot = file_name.rfind('.');
  if (dot == std::string_view::npos) return MeshFormat::kUnknown;
  const std::string extension = detail::lower_case(file_name.substr(dot + 1));
  if (extension == "obj") return MeshFormat::kObj;
  if (extension == "ply") return MeshFormat::kPly;
  if (extension == "off") return MeshFormat::kOff;
  if (extension == "stl") return MeshFormat::kStl;
  if (extension == "gltf") return MeshFormat::kGltf;
  if (extension == "glb") return MeshFormat::kGlb;
  return MeshFormat::kUnknown;
}

const char* mesh_format_name(MeshFormat format) {
  switch (format) {
    case MeshFormat::kObj:
      return "obj";
    case MeshFormat::kPly:
      return "ply";
    case MeshFormat::kOff:
      return "off";
    case MeshFormat::kStl:
      return "stl";
    case MeshFormat::kGltf:
      return "gltf";
    case MeshFormat::kGlb:
      return "glb";
    case MeshFormat::kUnknown:
      break;
  }
  return "unknown";
}

namespace {

Status read_from_memory(std::string_view bytes, MeshFormat format, Mesh& mesh,
                        ReadReport* report) {
  Mesh parsed;
  ReadReport parsed_report;
  Status status;
  switch (format) {
    case MeshFormat::kObj:
      status = detail::read_obj(bytes, parsed, parsed_report);
      break;
    case MeshFormat::kOff:
      status = detail::read_off(bytes, parsed, parsed_report);
      break;
    case MeshFormat::kPly:
      if (bytes.empty()) return Status(ErrorCode::kEmptyMesh, "no vertices or faces");
      status = detail::read_ply(bytes, parsed, parsed_report);
      break;
    case MeshFormat::kStl:
      if (bytes.empty()) return Status(ErrorCode::kEmptyMesh, "no vertices or faces");
      status = detail::read_with_openmesh(bytes, format, parsed, parsed_report);
      break;
    case MeshFormat::kGltf:
    case MeshFormat::kGlb:
      status = read_gltf(bytes, GltfReadOptions(), parsed, &parsed_report);
      break;
    case MeshFormat::kUnknown:
      return Status(ErrorCode::kUnsupportedFormat, "unknown mesh format (use .obj .ply .off .stl .gltf .glb)");
  }
  if (!status) return status;
  mesh = std::move(parsed);
  if (report != nullptr) *report = parsed_report;
  return Status::ok();
}

Status read_file(const std::string& path, Mesh& mesh, ReadReport* report) {
  const MeshFormat format = mesh_format_from_path(path);
  if (format == MeshFormat::kUnknown) {
    return Status(ErrorCode::kUnsupportedFormat, "unknown mesh format (use .obj .ply .off .stl .gltf .glb)");
  }
  auto describe_errno = [](const char* what, int error_number) {
    std::string reason = std::strerror(error_number);
    if (!reason.empty())
      reason[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(reason[0])));
    return Status(ErrorCode::kIoError, std::string(what) + " (" + reason + ")");
  };
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                       &std::fclose);
  if (!file) return describe_errno("cannot open file", errno);
  // The size from the file system is only a hint (pipes and /dev/stdin have none, files may
  // grow): read until end of file, the first read sized to hit it at once.
  std::error_code size_error;
  const uintmax_t size_hint = std::filesystem::file_size(path, size_error);
  // A buffer that is not zero-filled first, as std::string::resize would (a pass over the
  // whole file's worth of memory before fread writes it).
  std::size_t capacity =
      size_error ? (std::size_t{1} << 20) : static_cast<std::size_t>(size_hint) + 1;
  std::unique_ptr<char[]> bytes(new char[capacity]);
  std::size_t size = 0;
  for (;;) {
    const std::size_t got = std::fread(bytes.get() + size, 1, capacity - size, file.get());
    size += got;
    if (size < capacity) break;
    std::unique_ptr<char[]> larger(new char[2 * capacity]);
    std::memcpy(larger.get(), bytes.get(), size);
    bytes = std::move(larger);
    capacity *= 2;
  }
  if (std::ferror(file.get())) return describe_errno("cannot read file", errno);
  if (format == MeshFormat::kGltf || format == MeshFormat::kGlb) {
    // A .gltf's buffers may be files beside it.
    GltfReadOptions options;
    const std::filesystem::path directory = std::filesystem::path(path).parent_path();
    options.base_directory = directory.empty() ? "." : directory.string();
    return read_gltf(std::string_view(bytes.get(), size), options, mesh, report);
  }
  return read_from_memory(std::string_view(bytes.get(), size), format, mesh, report);
}

}  // namespace

Status read_mesh_from_memory(std::string_view bytes, MeshFormat format, Mesh& mesh,
                             ReadReport* report) {
  return detail::no_throw([&] { return read_from_memory(bytes, format, mesh, report); });
}

Status read_mesh(const std::string& path, Mesh& mesh, ReadReport* report) {
  return detail::no_throw([&] { return read_file(path, mesh, report); });
}

}  // namespace pm
