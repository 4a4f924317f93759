// Format detection, file reading and dispatch; PLY, OFF and STL through OpenMesh's readers.
//
// OpenMesh's readers normally feed a PolyMesh, whose add_face refuses non-manifold faces and
// so silently drops data. Here they feed RawMeshImporter instead, which only records the
// vertices and faces it is given, so what the encoder sees is exactly what the file holds.
//
// OpenMesh's stream readers trust their input more than a library reading user files can:
//  - Counts come from headers and drive loops and reserve(); a garbage count loops for a
//    very long time. The importer therefore ignores reserve() for allocation, caps the
//    number of elements by the input size, and aborts (by throwing through the reader) on
//    the first face that cannot be right.
//  - A truncated or malformed text body leaves the std::istream failed while the reader
//    keeps going, feeding stale values. For PLY and OFF the stream is switched to throw on
//    failure once the header has been read (the reader calls reserve() at that point), and
//    the numbers of vertices and faces received must match the header's.
//  - The OFF stream reader does not look at the header keyword: it uses whatever variant
//    (normals, colours, binary) the last file-based OFF read in the process detected, and it
//    understands neither comments nor counts on the header line. So the OFF text is
//    normalized first (see normalize_off) into the plain form that reader handles.
//  - The STL stream reader reads binary only when told to, and then trusts the triangle
//    count; the type is detected here, and a binary file's size must match its count.
// OpenMesh's readers keep state in process-wide singletons, so reads are serialized.

#include "pm/mesh_io.h"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>  // pulls in the reader registrations of OpenMeshCore
#include <OpenMesh/Core/IO/Options.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <ios>
#include <limits>
#include <memory>
#include <mutex>
#include <new>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "mesh_readers.h"

namespace pm {
namespace {

std::string lower_case(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

Status parse_error(std::string message) { return Status(ErrorCode::kParseError, std::move(message)); }

// ---------------------------------------------------------------------------------------------
// RawMeshImporter

// Thrown by the importer to stop an OpenMesh reader in the middle of a bad file.
struct AbortRead {
  std::string message;
};

class RawMeshImporter final : public OpenMesh::IO::BaseImporter {
 public:
  using VertexHandle = OpenMesh::VertexHandle;
  using FaceHandle = OpenMesh::FaceHandle;
  using HalfedgeHandle = OpenMesh::HalfedgeHandle;
  using EdgeHandle = OpenMesh::EdgeHandle;
  using Vec2f = OpenMesh::Vec2f;
  using Vec3f = OpenMesh::Vec3f;
  using Vec3d = OpenMesh::Vec3d;
  using Vec4f = OpenMesh::Vec4f;
  using Vec3uc = OpenMesh::Vec3uc;
  using Vec4uc = OpenMesh::Vec4uc;
  using StatusInfo = OpenMesh::Attributes::StatusInfo;

  // `max_elements` bounds vertices and face corners: no format stores one in less than a byte.
  RawMeshImporter(std::istream& in, std::size_t max_elements, bool throw_on_stream_failure)
      : in_(in), max_elements_(max_elements), throw_on_stream_failure_(throw_on_stream_failure) {}

  std::vector<float> positions;
  std::vector<int> corners;             // vertex indices of all faces, as received
  std::vector<uint32_t> corner_counts;  // per face
  bool header_counts_known = false;     // reserve() was called
  std::size_t header_vertices = 0;
  std::size_t header_faces = 0;

  // The readers call this once the header is parsed, with its counts.
  void reserve(unsigned int vertices, unsigned int /*edges*/, unsigned int faces) override {
    header_counts_known = true;
    header_vertices = vertices;
    header_faces = faces;
    // From here on a failed extraction means a malformed body: stop right there rather than
    // let the reader loop on with stale values (std::ios_base::failure propagates out).
    if (throw_on_stream_failure_) in_.exceptions(std::ios_base::failbit | std::ios_base::badbit);
  }

  VertexHandle add_vertex(const Vec3f& point) override {
    check_stream();
    if (vertex_count() >= max_elements_ ||
        vertex_count() >= static_cast<std::size_t>(std::numeric_limits<int>::max())) {
      throw AbortRead{"more vertices than the file can hold"};
    }
    positions.insert(positions.end(), {point[0], point[1], point[2]});
    return VertexHandle(static_cast<int>(vertex_count() - 1));
  }
  VertexHandle add_vertex() override { return add_vertex(Vec3f(0.0f, 0.0f, 0.0f)); }
  void set_point(VertexHandle vertex, const Vec3f& point) override {
    check_stream();
    const std::size_t index = static_cast<std::size_t>(vertex.idx());
    if (vertex.idx() < 0 || index >= vertex_count()) throw AbortRead{"invalid vertex handle"};
    std::memcpy(&positions[3 * index], point.data(), 3 * sizeof(float));
  }

  FaceHandle add_face(const VHandles& face) override {
    check_stream();
    const std::size_t face_index = corner_counts.size();
    if (face.size() < 3) {
      throw AbortRead{"face " + std::to_string(face_index) + " has fewer than 3 corners"};
    }
    if (corners.size() + face.size() > max_elements_) {
      throw AbortRead{"more face corners than the file can hold"};
    }
    for (VertexHandle vertex : face) corners.push_back(vertex.idx());
    corner_counts.push_back(static_cast<uint32_t>(face.size()));
    return FaceHandle(static_cast<int>(face_index));
  }

  std::size_t vertex_count() const { return positions.size() / 3; }

  size_t n_vertices() const override { return vertex_count(); }
  size_t n_faces() const override { return corner_counts.size(); }
  size_t n_edges() const override { return 0; }

  // Everything else a reader may hand over (normals, colours, texture coordinates, status,
  // topology) is not part of a pm::Mesh.
  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
  FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f>&) override {}
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_normal(VertexHandle, const Vec3f&) override {}
  void set_normal(VertexHandle, const Vec3d&) override {}
  void set_color(VertexHandle, const Vec3uc&) override {}
  void set_color(VertexHandle, const Vec4uc&) override {}
  void set_color(VertexHandle, const Vec3f&) override {}
  void set_color(VertexHandle, const Vec4f&) override {}
  void set_texcoord(VertexHandle, const Vec2f&) override {}
  void set_texcoord(VertexHandle, const Vec3f&) override {}
  void set_status(VertexHandle, const StatusInfo&) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HalfedgeHandle, const Vec2f&) override {}
  void set_texcoord(HalfedgeHandle, const Vec3f&) override {}
  void set_status(HalfedgeHandle, const StatusInfo&) override {}
  void set_color(EdgeHandle, const Vec3uc&) override {}
  void set_color(EdgeHandle, const Vec4uc&) override {}
  void set_color(EdgeHandle, const Vec3f&) override {}
  void set_color(EdgeHandle, const Vec4f&) override {}
  void set_status(EdgeHandle, const StatusInfo&) override {}
  void set_normal(FaceHandle, const Vec3f&) override {}
  void set_normal(FaceHandle, const Vec3d&) override {}
  void set_color(FaceHandle, const Vec3uc&) override {}
  void set_color(FaceHandle, const Vec4uc&) override {}
  void set_color(FaceHandle, const Vec3f&) override {}
  void set_color(FaceHandle, const Vec4f&) override {}
  void set_status(FaceHandle, const StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}

 private:
  // Callbacks after a failed extraction carry stale or default values: never record them.
  void check_stream() const {
    if (in_.fail()) throw AbortRead{"truncated or malformed data"};
  }

  std::istream& in_;
  std::size_t max_elements_;
  bool throw_on_stream_failure_;
};

// Validates what the importer received and turns it into a triangle mesh.
Status build_mesh(RawMeshImporter& raw, Mesh& mesh, ReadReport& report) {
  const std::size_t vertices = raw.vertex_count();
  if (vertices > std::numeric_limits<uint32_t>::max()) {
    return Status(ErrorCode::kResourceLimit, "more vertices than 32-bit indices can address");
  }
  for (std::size_t v = 0; v < vertices; ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      if (!std::isfinite(raw.positions[3 * v + axis])) {
        return parse_error("vertex " + std::to_string(v) + " has a non-finite coordinate");
      }
    }
  }
  mesh.positions = std::move(raw.positions);
  mesh.triangles.clear();
  report = ReadReport();
  std::size_t first_corner = 0;
  for (std::size_t face = 0; face < raw.corner_counts.size(); ++face) {
    const uint32_t count = raw.corner_counts[face];
    const int* corners = raw.corners.data() + first_corner;
    for (uint32_t i = 0; i < count; ++i) {
      if (corners[i] < 0 || static_cast<std::size_t>(corners[i]) >= vertices) {
        return parse_error("face " + std::to_string(face) + " uses vertex " + std::to_string(corners[i]) +
                           " of " + std::to_string(vertices));
      }
    }
    if (count > 3) ++report.polygons_triangulated;
    for (uint32_t i = 1; i + 1 < count; ++i) {
      mesh.triangles.insert(mesh.triangles.end(), {static_cast<uint32_t>(corners[0]),
                                                   static_cast<uint32_t>(corners[i]),
                                                   static_cast<uint32_t>(corners[i + 1])});
    }
    first_corner += count;
  }
  if (vertices == 0) return Status(ErrorCode::kEmptyMesh, "no vertices or faces");
  return Status::ok();
}

// ---------------------------------------------------------------------------------------------
// OFF normalization

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Splits a line into blank-separated tokens, up to a '#' comment.
std::vector<std::string_view> split_tokens(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    if (i == line.size() || line[i] == '#') break;
    std::size_t start = i;
    while (i < line.size() && !is_space(line[i]) && line[i] != '#') ++i;
    tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

bool parse_count(std::string_view token, uint64_t& value) {
  auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && ptr == token.data() + token.size();
}

// Rewrites an ASCII OFF file into the form OpenMesh's stream reader handles: the line "OFF",
// the line "<vertices> <faces> 0", then the body without comments and ending in a newline.
// Accepts comment and blank lines, counts on the header line, and the [ST][C][N]OFF variants
// (the extra per-vertex values are skipped by the reader). Rejects 4OFF, nOFF and binary OFF.
Status normalize_off(std::string_view bytes, std::string& normalized, uint64_t& vertices,
                     uint64_t& faces) {
  std::size_t pos = 0;
  auto next_content_line = [&](std::vector<std::string_view>& tokens) {
    while (pos < bytes.size()) {
      std::size_t eol = bytes.find('\n', pos);
      if (eol == std::string_view::npos) eol = bytes.size();
      tokens = split_tokens(bytes.substr(pos, eol - pos));
      pos = eol == bytes.size() ? eol : eol + 1;
      if (!tokens.empty()) return true;
    }
    return false;
  };

  std::vector<std::string_view> tokens;
  if (!next_content_line(tokens)) return Status(ErrorCode::kEmptyMesh, "no vertices or faces");
  std::string_view keyword = tokens[0];
  const std::string_view off = "OFF";
  if (keyword.size() < off.size() || keyword.substr(keyword.size() - off.size()) != off) {
    return parse_error("not a valid off file (no OFF header)");
  }
  std::string_view prefix = keyword.substr(0, keyword.size() - off.size());
  if (prefix.substr(0, 2) == "ST") prefix.remove_prefix(2);
  if (!prefix.empty() && prefix[0] == 'C') prefix.remove_prefix(1);
  if (!prefix.empty() && prefix[0] == 'N') prefix.remove_prefix(1);
  if (!prefix.empty()) {
    return Status(ErrorCode::kUnsupportedFormat,
                  "unsupported off variant " + std::string(keyword) + " (4OFF and nOFF are not supported)");
  }
  tokens.erase(tokens.begin());
  if (!tokens.empty() && lower_case(tokens[0]) == "binary") {
    return Status(ErrorCode::kUnsupportedFormat, "binary off is not supported");
  }
  if (tokens.empty() && !next_content_line(tokens)) return parse_error("off header has no counts");
  if (tokens.size() < 2 || tokens.size() > 3 || !parse_count(tokens[0], vertices) ||
      !parse_count(tokens[1], faces)) {
    return parse_error("malformed off counts (expected: vertices faces edges)");
  }
  const std::string_view body = bytes.substr(pos);
  // The shortest vertex line is "0 0 0\n", the shortest face line "3 0 0 0\n".
  constexpr uint64_t kLimit = uint64_t{1} << 40;
  if (vertices > kLimit || faces > kLimit || 6 * vertices + 8 * faces > body.size() + 1) {
    return parse_error("off header declares " + std::to_string(vertices) + " vertices and " +
                       std::to_string(faces) + " faces, more than the file holds");
  }

  normalized.clear();
  normalized.reserve(body.size() + 64);
  normalized += "OFF\n";
  normalized += std::to_string(vertices);
  normalized += ' ';
  normalized += std::to_string(faces);
  normalized += " 0\n";
  // Comments may also follow values; cut each from '#' to the end of its line.
  std::size_t i = 0;
  while (i < body.size()) {
    const std::size_t hash = body.find('#', i);
    if (hash == std::string_view::npos) {
      normalized.append(body.substr(i));
      break;
    }
    normalized.append(body.substr(i, hash - i));
    const std::size_t eol = body.find('\n', hash);
    i = eol == std::string_view::npos ? body.size() : eol;
  }
  // The reader takes the rest of each vertex line with getline, which fails (and so would
  // abort the read) on a last line without a newline.
  if (normalized.back() != '\n') normalized += '\n';
  return Status::ok();
}

// ---------------------------------------------------------------------------------------------
// OpenMesh reading

std::mutex& openmesh_mutex() {
  static std::mutex mutex;
  return mutex;
}

// The library never prints; OpenMesh logs through these streams by default.
void silence_openmesh() {
  omerr().disable();
  omlog().disable();
  omout().disable();
}

enum class StlKind { kAscii, kBinary, kInvalid };

StlKind detect_stl(std::string_view bytes) {
  // Binary first: its 80-byte header may well begin with "solid" too.
  if (bytes.size() >= 84) {
    const auto* count_bytes = reinterpret_cast<const unsigned char*>(bytes.data() + 80);
    const uint64_t triangles = uint64_t{count_bytes[0]} | uint64_t{count_bytes[1]} << 8 |
                               uint64_t{count_bytes[2]} << 16 | uint64_t{count_bytes[3]} << 24;
    if (84 + 50 * triangles == bytes.size()) return StlKind::kBinary;
  }
  std::size_t i = 0;
  while (i < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[i]))) ++i;
  if (lower_case(bytes.substr(i, 5)) == "solid") return StlKind::kAscii;
  return StlKind::kInvalid;
}

Status read_with_openmesh(std::string_view bytes, MeshFormat format, Mesh& mesh, ReadReport& report) {
  const char* const name = mesh_format_name(format);
  std::string text;  // what OpenMesh reads, when it is not `bytes` as is
  OpenMesh::IO::Options options;
  bool throw_on_stream_failure = true;
  uint64_t off_vertices = 0;
  uint64_t off_faces = 0;
  switch (format) {
    case MeshFormat::kPly:
      if (bytes.substr(0, 3) != "ply") return parse_error("not a valid ply file");
      break;
    case MeshFormat::kOff: {
      Status status = normalize_off(bytes, text, off_vertices, off_faces);
      if (!status) return status;
      bytes = text;
      break;
    }
    case MeshFormat::kStl: {
      // OpenMesh's STL reader merges vertices with equal positions (STL has no indices, so
      // that is the only way to get a connected mesh) and then skips faces that this made
      // degenerate, i.e. triangles with two identical corner positions are dropped.
      const StlKind kind = detect_stl(bytes);
      if (kind == StlKind::kInvalid) return parse_error("not a valid stl file");
      if (kind == StlKind::kBinary) options += OpenMesh::IO::Options::Binary;
      // The ASCII reader reads lines until the end, which fails the stream at the end.
      throw_on_stream_failure = false;
      break;
    }
    default:
      return Status(ErrorCode::kInternal, "no openmesh reader for this format");
  }

  // The reader sees a copy; std::istringstream cannot wrap memory it does not own.
  std::istringstream in(std::string(bytes), std::ios_base::in | std::ios_base::binary);
  RawMeshImporter importer(in, bytes.size(), throw_on_stream_failure);
  bool ok = false;
  std::string abort_message;
  try {
    std::lock_guard<std::mutex> lock(openmesh_mutex());
    silence_openmesh();
    ok = OpenMesh::IO::IOManager().read(in, name, importer, options);
  } catch (const AbortRead& abort) {
    abort_message = abort.message;
  } catch (const std::ios_base::failure&) {
    abort_message = "truncated or malformed data";
  } catch (const std::bad_alloc&) {
    return Status(ErrorCode::kResourceLimit, std::string("out of memory reading ") + name + " file");
  } catch (const std::exception& e) {
    abort_message = lower_case(e.what());
  }
  if (!abort_message.empty()) return parse_error(std::string("invalid ") + name + " file: " + abort_message);
  if (!ok) return parse_error(std::string("not a valid ") + name + " file");

  if (format == MeshFormat::kOff) {
    // The reader must have seen the header we wrote (see normalize_off).
    if (!importer.header_counts_known || importer.header_vertices != off_vertices ||
        importer.header_faces != off_faces) {
      return parse_error("invalid off file: the reader did not understand the header");
    }
  }
  if (importer.header_counts_known && format != MeshFormat::kStl) {
    if (importer.vertex_count() != importer.header_vertices) {
      return parse_error(std::string("invalid ") + name + " file: header declares " +
                         std::to_string(importer.header_vertices) + " vertices, found " +
                         std::to_string(importer.vertex_count()));
    }
    if (importer.n_faces() != importer.header_faces) {
      return parse_error(std::string("invalid ") + name + " file: header declares " +
                         std::to_string(importer.header_faces) + " faces, found " +
                         std::to_string(importer.n_faces()));
    }
  }
  return build_mesh(importer, mesh, report);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Public API

MeshFormat mesh_format_from_path(std::string_view path) {
  const std::size_t slash = path.find_last_of("/\\");
  const std::string_view file_name = slash == std::string_view::npos ? path : path.substr(slash + 1);
  const std::size_t dot = file_name.rfind('.');
  if (dot == std::string_view::npos) return MeshFormat::kUnknown;
  const std::string extension = lower_case(file_name.substr(dot + 1));
  if (extension == "obj") return MeshFormat::kObj;
  if (extension == "ply") return MeshFormat::kPly;
  if (extension == "off") return MeshFormat::kOff;
  if (extension == "stl") return MeshFormat::kStl;
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
    case MeshFormat::kUnknown:
      break;
  }
  return "unknown";
}

Status read_mesh_from_memory(std::string_view bytes, MeshFormat format, Mesh& mesh, ReadReport* report) {
  Mesh parsed;
  ReadReport parsed_report;
  Status status;
  switch (format) {
    case MeshFormat::kObj:
      status = detail::read_obj(bytes, parsed, parsed_report);
      break;
    case MeshFormat::kPly:
    case MeshFormat::kOff:
    case MeshFormat::kStl:
      if (bytes.empty()) return Status(ErrorCode::kEmptyMesh, "no vertices or faces");
      status = read_with_openmesh(bytes, format, parsed, parsed_report);
      break;
    case MeshFormat::kUnknown:
      return Status(ErrorCode::kUnsupportedFormat, "unknown mesh format (use .obj .ply .off .stl)");
  }
  if (!status) return status;
  mesh = std::move(parsed);
  if (report != nullptr) *report = parsed_report;
  return Status::ok();
}

Status read_mesh(const std::string& path, Mesh& mesh, ReadReport* report) {
  const MeshFormat format = mesh_format_from_path(path);
  if (format == MeshFormat::kUnknown) {
    return Status(ErrorCode::kUnsupportedFormat, "unknown mesh format (use .obj .ply .off .stl)");
  }
  auto describe_errno = [](const char* what, int error_number) {
    std::string reason = std::strerror(error_number);
    if (!reason.empty()) reason[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(reason[0])));
    return Status(ErrorCode::kIoError, std::string(what) + " (" + reason + ")");
  };
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) return describe_errno("cannot open file", errno);
  // The size from the file system is only a hint (pipes and /dev/stdin have none, files may
  // grow): read until end of file, the first read sized to hit it at once.
  std::error_code size_error;
  const uintmax_t size_hint = std::filesystem::file_size(path, size_error);
  std::size_t chunk = size_error ? (std::size_t{1} << 20) : static_cast<std::size_t>(size_hint) + 1;
  std::string bytes;
  for (;;) {
    const std::size_t old_size = bytes.size();
    bytes.resize(old_size + chunk);
    const std::size_t got = std::fread(bytes.data() + old_size, 1, chunk, file.get());
    bytes.resize(old_size + got);
    if (got < chunk) break;
    chunk = std::max(chunk, std::size_t{1} << 20);
  }
  if (std::ferror(file.get())) return describe_errno("cannot read file", errno);
  return read_mesh_from_memory(bytes, format, mesh, report);
}

}  // namespace pm
