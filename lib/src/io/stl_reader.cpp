// The STL reader: OpenMesh's, fed to an importer that records what the file holds, behind
// checks that OpenMesh's STL reader does not make (read_with_openmesh below).
//
// OpenMesh's STL reader normally feeds a PolyMesh, whose add_face refuses non-manifold faces
// and so silently drops data. Here it feeds RawMeshImporter instead, which only records the
// vertices and faces it is given, so what the encoder sees is exactly what the file holds.
//
// OpenMesh's stream readers trust their input more than a library reading user files can:
//  - Counts come from headers and drive loops; a garbage count loops for a very long time.
//    The importer therefore ignores reserve() for allocation, caps the number of elements
//    by the input size, and aborts (by throwing through the reader) on the first face that
//    cannot be right.
//  - The STL stream reader reads binary only when told to, and then trusts the triangle
//    count; the type is detected here, and a binary file's size must match its count. Its
//    ASCII reader accepts malformed numbers as garbage coordinates, so ASCII STL is
//    validated first (validate_ascii_stl).
//  - Text numbers are read with iostreams; ours are imbued with the classic locale, but
//    streams OpenMesh makes itself (STL ASCII lines) use the global C++ locale, so a
//    program must not make a locale with a decimal comma global.
// OpenMesh's readers keep state in process-wide singletons, so reads are serialized.

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>  // pulls in the reader registrations of OpenMeshCore
#include <OpenMesh/Core/IO/Options.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <ios>
#include <limits>
#include <locale>
#include <mutex>
#include <new>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "io/mesh_readers.h"
#include "io/openmesh_logs.h"
#include "io/reader_support.h"

namespace pm::detail {
namespace {

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

  // Everything else a reader may hand over: STL's reader hands over facet normals (derived
  // from the corners, so nothing is lost) and nothing else; status and topology are not part
  // of a pm::Mesh.
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
        return parse_error("face " + std::to_string(face) + " uses vertex " +
                           std::to_string(corners[i]) + " of " + std::to_string(vertices));
      }
    }
    if (count > 3) ++report.polygons_triangulated;
    for (uint32_t i = 1; i + 1 < count; ++i) {
      mesh.triangles.insert(mesh.triangles.end(),
                            {static_cast<uint32_t>(corners[0]), static_cast<uint32_t>(corners[i]),
                             static_cast<uint32_t>(corners[i + 1])});
    }
    first_corner += count;
  }
  if (vertices == 0) return Status(ErrorCode::kEmptyMesh, "no vertices or faces");
  return Status::ok();
}

std::mutex& openmesh_mutex() {
  static std::mutex mutex;
  return mutex;
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

// Checks that ASCII STL text follows the grammar, one statement per line:
//   solid [name] { facet normal x y z / outer loop / vertex x y z (3 times) / endloop /
//   endfacet } endsolid [name], possibly several solids.
// OpenMesh's ASCII reader does not check: it reads "vertex 1,5 0 0" as (1, 0, 0), accepts
// words for numbers, and silently drops a facet with a NaN or with two vertices.
Status validate_ascii_stl(std::string_view bytes) {
  enum class Expect { kSolid, kFacetOrEndsolid, kOuterLoop, kVertex, kEndloop, kEndfacet };
  Expect expect = Expect::kSolid;
  int vertices_in_loop = 0;
  std::size_t line_number = 0;
  std::size_t pos = 0;
  auto error = [&line_number](const std::string& what) {
    return parse_error("line " + std::to_string(line_number) + ": " + what);
  };
  // Whether tokens[first..] are exactly three finite numbers.
  auto three_numbers = [](const std::vector<std::string_view>& tokens, std::size_t first) {
    if (tokens.size() != first + 3) return false;
    for (std::size_t i = first; i < first + 3; ++i) {
      const char* p = tokens[i].data();
      const char* const end = p + tokens[i].size();
      float value = 0;
      if (detail::parse_float(p, end, value) != detail::NumberResult::kOk || p != end ||
          !std::isfinite(value)) {
        return false;
      }
    }
    return true;
  };
  while (pos < bytes.size()) {
    ++line_number;
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string_view::npos) eol = bytes.size();
    const std::string_view line = bytes.substr(pos, eol - pos);
    pos = eol == bytes.size() ? eol : eol + 1;
    const std::vector<std::string_view> tokens = split_tokens(line);
    if (tokens.empty()) continue;
    const std::string_view keyword = tokens[0];
    switch (expect) {
      case Expect::kSolid:
        // The name is free text.
        if (keyword != "solid") return error("expected solid");
        expect = Expect::kFacetOrEndsolid;
        break;
      case Expect::kFacetOrEndsolid:
        if (keyword == "endsolid") {
          expect = Expect::kSolid;
        } else if (keyword == "facet" && tokens.size() >= 2 && tokens[1] == "normal" &&
                   three_numbers(tokens, 2)) {
          expect = Expect::kOuterLoop;
        } else {
          return error("expected facet normal x y z, or endsolid");
        }
        break;
      case Expect::kOuterLoop:
        if (tokens.size() != 2 || keyword != "outer" || tokens[1] != "loop") {
          return error("expected outer loop");
        }
        expect = Expect::kVertex;
        vertices_in_loop = 0;
        break;
      case Expect::kVertex:
        if (keyword != "vertex") return error("expected vertex x y z");
        if (!three_numbers(tokens, 1)) return error("malformed vertex");
        if (++vertices_in_loop == 3) expect = Expect::kEndloop;
        break;
      case Expect::kEndloop:
        if (tokens.size() != 1 || keyword != "endloop") return error("expected endloop");
        expect = Expect::kEndfacet;
        break;
      case Expect::kEndfacet:
        if (tokens.size() != 1 || keyword != "endfacet") return error("expected endfacet");
        expect = Expect::kFacetOrEndsolid;
        break;
    }
  }
  if (expect != Expect::kSolid) return error("file ends inside a solid");
  return Status::ok();
}

}  // namespace

Status read_with_openmesh(std::string_view bytes, MeshFormat format, Mesh& mesh,
                          ReadReport& report) {
  const char* const name = mesh_format_name(format);
  OpenMesh::IO::Options options;
  bool throw_on_stream_failure = true;
  switch (format) {
    case MeshFormat::kStl: {
      // OpenMesh's STL reader merges vertices with equal positions (STL has no indices, so
      // that is the only way to get a connected mesh) and then skips faces that this made
      // degenerate, i.e. triangles with two identical corner positions are dropped.
      const StlKind kind = detect_stl(bytes);
      if (kind == StlKind::kInvalid) return parse_error("not a valid stl file");
      if (kind == StlKind::kBinary) options += OpenMesh::IO::Options::Binary;
      if (kind == StlKind::kAscii) {
        if (Status status = validate_ascii_stl(bytes); !status) return status;
      }
      // The ASCII reader reads lines until the end, which fails the stream at the end.
      throw_on_stream_failure = false;
      break;
    }
    default:
      return Status(ErrorCode::kInternal, "no openmesh reader for this format");
  }

  // The reader sees a copy; std::istringstream cannot wrap memory it does not own.
  std::istringstream in(std::string(bytes), std::ios_base::in | std::ios_base::binary);
  in.imbue(std::locale::classic());
  RawMeshImporter importer(in, bytes.size(), throw_on_stream_failure);
  bool ok = false;
  std::string abort_message;
  try {
    std::lock_guard<std::mutex> lock(openmesh_mutex());
    const QuietOpenMeshLogs quiet;
    ok = OpenMesh::IO::IOManager().read(in, name, importer, options);
  } catch (const AbortRead& abort) {
    abort_message = abort.message;
  } catch (const std::ios_base::failure&) {
    abort_message = "truncated or malformed data";
  } catch (const std::bad_alloc&) {
    return Status(ErrorCode::kResourceLimit,
                  std::string("out of memory reading ") + name + " file");
  } catch (const std::exception& e) {
    abort_message = lower_case(e.what());
  }
  if (!abort_message.empty())
    return parse_error(std::string("invalid ") + name + " file: " + abort_message);
  if (!ok) return parse_error(std::string("not a valid ") + name + " file");

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

}  // namespace pm::detail
