// Mesh writers: OBJ and OFF text, PLY binary little-endian, STL binary.
//
// Everything is appended to one std::string reserved up front; floats are printed with
// std::to_chars (shortest text that reads back to the same float32 bits, locale-independent),
// and binary values are stored byte by byte in little-endian order whatever the host's.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include "pm/mesh_io.h"

namespace pm {
namespace {

// Appends characters at a raw cursor: no per-call size bookkeeping in the hot loops. The
// caller guarantees capacity with ensure(), which makes room for the next write.
class TextBuilder {
 public:
  explicit TextBuilder(std::string& out) : out_(out) {}

  void ensure(std::size_t bytes) {
    if (static_cast<std::size_t>(end_ - cursor_) >= bytes) return;
    const std::size_t used = size();
    out_.resize(std::max(out_.size() * 2, used + bytes + 4096));
    cursor_ = out_.data() + used;
    end_ = out_.data() + out_.size();
  }
  void begin(std::size_t expected) {
    out_.clear();
    out_.resize(expected);
    cursor_ = out_.data();
    end_ = cursor_ + out_.size();
  }
  void finish() { out_.resize(size()); }

  void put(char c) { *cursor_++ = c; }
  void put(std::string_view text) {
    std::memcpy(cursor_, text.data(), text.size());
    cursor_ += text.size();
  }
  void put(float value) { cursor_ = std::to_chars(cursor_, end_, value).ptr; }
  void put(uint64_t value) { cursor_ = std::to_chars(cursor_, end_, value).ptr; }
  // "x y z\n" and "a b c\n" (indices plus first_index), the lines OBJ and OFF share.
  void put_xyz_line(const float* p) {
    put(p[0]);
    put(' ');
    put(p[1]);
    put(' ');
    put(p[2]);
    put('\n');
  }
  void put_index_line(const uint32_t* t, uint64_t first_index) {
    put(t[0] + first_index);
    put(' ');
    put(t[1] + first_index);
    put(' ');
    put(t[2] + first_index);
    put('\n');
  }

  void put_u8(uint8_t value) { *cursor_++ = static_cast<char>(value); }
  void put_u16(uint16_t value) {
    put_u8(static_cast<uint8_t>(value));
    put_u8(static_cast<uint8_t>(value >> 8));
  }
  void put_u32(uint32_t value) {
    for (int shift = 0; shift < 32; shift += 8) put_u8(static_cast<uint8_t>(value >> shift));
  }
  void put_f32(float value) {
    uint32_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    put_u32(bits);
  }

 private:
  std::size_t size() const { return static_cast<std::size_t>(cursor_ - out_.data()); }

  std::string& out_;
  char* cursor_ = nullptr;
  char* end_ = nullptr;
};

// Longest outputs: a float is at most 15 characters ("-1.17549435e-38"), a uint32 10.
constexpr std::size_t kMaxFloatChars = 16;
constexpr std::size_t kMaxIndexChars = 10;
constexpr std::size_t kMaxVertexLine = 2 + 3 * (kMaxFloatChars + 1);  // "v " + "x y z\n"
constexpr std::size_t kMaxFaceLine = 2 + 3 * (kMaxIndexChars + 1);    // "f " + "a b c\n"

Status validate(const Mesh& mesh) {
  if (mesh.positions.size() % 3 != 0 || mesh.triangles.size() % 3 != 0) {
    return Status(ErrorCode::kInvalidArgument, "mesh arrays are not a multiple of 3 long");
  }
  const std::size_t vertices = mesh.vertex_count();
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!std::isfinite(mesh.positions[i])) {
      return Status(ErrorCode::kInvalidArgument,
                    "vertex " + std::to_string(i / 3) + " has a non-finite coordinate");
    }
  }
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (mesh.triangles[i] >= vertices) {
      return Status(ErrorCode::kInvalidArgument, "face " + std::to_string(i / 3) + " uses vertex " +
                                                     std::to_string(mesh.triangles[i]) + " of " +
                                                     std::to_string(vertices));
    }
  }
  return Status::ok();
}

void write_obj(const Mesh& mesh, std::string& bytes) {
  TextBuilder out(bytes);
  out.begin(mesh.vertex_count() * 32 + mesh.face_count() * 24 + 64);
  const float* p = mesh.positions.data();
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v, p += 3) {
    out.ensure(kMaxVertexLine);
    out.put("v ");
    out.put_xyz_line(p);
  }
  const uint32_t* t = mesh.triangles.data();
  for (std::size_t f = 0; f < mesh.face_count(); ++f, t += 3) {
    out.ensure(kMaxFaceLine);
    out.put("f ");
    out.put_index_line(t, 1);
  }
  out.finish();
}

void write_off(const Mesh& mesh, std::string& bytes) {
  TextBuilder out(bytes);
  out.begin(mesh.vertex_count() * 30 + mesh.face_count() * 24 + 64);
  out.put("OFF\n");
  out.put(uint64_t{mesh.vertex_count()});
  out.put(' ');
  out.put(uint64_t{mesh.face_count()});
  out.put(" 0\n");
  const float* p = mesh.positions.data();
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v, p += 3) {
    out.ensure(kMaxVertexLine);
    out.put_xyz_line(p);
  }
  const uint32_t* t = mesh.triangles.data();
  for (std::size_t f = 0; f < mesh.face_count(); ++f, t += 3) {
    out.ensure(kMaxFaceLine);
    out.put("3 ");
    out.put_index_line(t, 0);
  }
  out.finish();
}

Status write_ply(const Mesh& mesh, std::string& bytes) {
  // PLY "int" indices are signed 32-bit.
  if (mesh.vertex_count() > static_cast<std::size_t>(std::numeric_limits<int32_t>::max())) {
    return Status(ErrorCode::kResourceLimit, "too many vertices for ply int indices");
  }
  std::string header =
      "ply\n"
      "format binary_little_endian 1.0\n"
      "element vertex " +
      std::to_string(mesh.vertex_count()) +
      "\n"
      "property float x\n"
      "property float y\n"
      "property float z\n"
      "element face " +
      std::to_string(mesh.face_count()) +
      "\n"
      "property list uchar int vertex_indices\n"
      "end_header\n";
  TextBuilder out(bytes);
  out.begin(header.size() + mesh.positions.size() * 4 + mesh.face_count() * 13);
  out.put(header);
  for (float coordinate : mesh.positions) out.put_f32(coordinate);
  const uint32_t* t = mesh.triangles.data();
  for (std::size_t f = 0; f < mesh.face_count(); ++f, t += 3) {
    out.put_u8(3);
    out.put_u32(t[0]);
    out.put_u32(t[1]);
    out.put_u32(t[2]);
  }
  out.finish();
  return Status::ok();
}

Status write_stl(const Mesh& mesh, std::string& bytes) {
  if (mesh.face_count() > std::numeric_limits<uint32_t>::max()) {
    return Status(ErrorCode::kResourceLimit, "too many faces for binary stl");
  }
  TextBuilder out(bytes);
  out.begin(84 + mesh.face_count() * 50);
  // The header must not start with "solid", which would make readers take it for ASCII STL.
  std::string header = "binary stl written by pm";
  header.resize(80, ' ');
  out.put(header);
  out.put_u32(static_cast<uint32_t>(mesh.face_count()));
  const float* positions = mesh.positions.data();
  const uint32_t* t = mesh.triangles.data();
  for (std::size_t f = 0; f < mesh.face_count(); ++f, t += 3) {
    const float* a = positions + 3 * std::size_t{t[0]};
    const float* b = positions + 3 * std::size_t{t[1]};
    const float* c = positions + 3 * std::size_t{t[2]};
    // The facet normal, by the right-hand rule; zero for a degenerate triangle.
    const double ab[3] = {double{b[0]} - a[0], double{b[1]} - a[1], double{b[2]} - a[2]};
    const double ac[3] = {double{c[0]} - a[0], double{c[1]} - a[1], double{c[2]} - a[2]};
    double normal[3] = {ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2],
                        ab[0] * ac[1] - ab[1] * ac[0]};
    const double length =
        std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    for (double& component : normal)
      component = length > 0 && std::isfinite(length) ? component / length : 0.0;
    for (double component : normal) out.put_f32(static_cast<float>(component));
    for (const float* corner : {a, b, c}) {
      out.put_f32(corner[0]);
      out.put_f32(corner[1]);
      out.put_f32(corner[2]);
    }
    out.put_u16(0);  // attribute byte count
  }
  out.finish();
  return Status::ok();
}

}  // namespace

Status write_mesh_to_memory(const Mesh& mesh, MeshFormat format, std::string& bytes) {
  if (format == MeshFormat::kUnknown) {
    return Status(ErrorCode::kUnsupportedFormat, "unknown mesh format (use .obj .ply .off .stl)");
  }
  if (Status status = validate(mesh); !status) return status;
  switch (format) {
    case MeshFormat::kObj:
      write_obj(mesh, bytes);
      return Status::ok();
    case MeshFormat::kOff:
      write_off(mesh, bytes);
      return Status::ok();
    case MeshFormat::kPly:
      return write_ply(mesh, bytes);
    case MeshFormat::kStl:
      return write_stl(mesh, bytes);
    case MeshFormat::kUnknown:
      break;
  }
  return Status(ErrorCode::kInternal, "unhandled mesh format");
}

}  // namespace pm
