// The size benchmark (issue 5): pm's .pm stream against what people store meshes in, on one
// mesh per call, one markdown table row out.
//
//   pm_bench_size MESH [--work DIR]
//
// Columns (bytes, and bits per vertex of the input):
//   raw zstd        zstd -19 of the mesh as raw binary: float32 xyz per vertex, uint32 per
//                   triangle corner (what the issue compares against)
//   raw+attr zstd   the same with the attributes a .pm carries: the texture-coordinate and
//                   normal tables (float32), a uint32 id per corner for each, float32 colours,
//                   a uint32 material per face
//   OpenMesh .pm    OpenMesh-mkbalancedpm's progressive mesh of the file (24 bytes per split)
//   pm lossless     pmenc's stream, default options: every float bit, every attribute
//   pm geometry     the same encoded with --drop-attributes, for meshes with attributes (what
//                   OpenMesh's .pm and the raw zstd column hold)
//   draco q14       draco_encoder -qp 14 -cl 10 (its defaults for the rest: 10-bit texture
//                   coordinates, 8-bit normals); single resolution
//   pm q14          pmenc --quantize 14 --quantize-uv 10 --quantize-normal 8: the same bits
//                   as draco's, still every level of detail (splits in layers within windows
//                   of 1/16 of the vertices, the default; errors with pmenc's 5 significant
//                   bits)
//   pm q14 layered  the same with pmenc --layered (splits in layers within whole chunks)
//   pm q14 greedy   the same with pmenc --layer-window 0 (the simplifier's order)
// The external tools run as processes (std::system); a missing tool gives "n/a".
#include <zstd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "pm/advanced/pm_stream.h"
#include "pm/encoder.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"

namespace {

[[noreturn]] void die(const std::string& message) {
  std::fprintf(stderr, "pm_bench_size: %s\n", message.c_str());
  std::exit(1);
}

template <typename T>
void append(std::string& out, const std::vector<T>& values) {
  out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

std::size_t zstd19(const std::string& raw) {
  std::string frame(ZSTD_compressBound(raw.size()), '\0');
  const std::size_t n = ZSTD_compress(frame.data(), frame.size(), raw.data(), raw.size(), 19);
  if (ZSTD_isError(n)) die("zstd failed");
  return n;
}

long long file_size(const std::string& path) {
  std::error_code error;
  const auto size = std::filesystem::file_size(path, error);
  return error ? -1 : static_cast<long long>(size);
}

std::size_t pm_size(const pm::ProgressiveMesh& progressive, int bits, int uv_bits, int normal_bits) {
  pm::WriteOptions options;
  options.position_bits = bits;
  options.uv_bits = uv_bits;
  options.normal_bits = normal_bits;
  options.error_bits = bits > 0 ? pm::kQuantizedErrorBits : 0;  // as pmenc --quantize
  std::string bytes;
  if (pm::Status s = pm::write_pm(progressive, options, bytes); !s) die("write_pm: " + s.message());
  return bytes.size();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) die("usage: pm_bench_size MESH [--work DIR]");
  const std::string path = argv[1];
  std::string work = std::filesystem::temp_directory_path().string();
  if (argc == 4 && std::string(argv[2]) == "--work") work = argv[3];
  pm::Mesh mesh;
  if (pm::Status s = pm::read_mesh(path, mesh); !s) die(path + ": " + s.message());

  std::string geometry;
  append(geometry, mesh.positions);
  append(geometry, mesh.triangles);
  std::string attributed = geometry;
  append(attributed, mesh.uvs);
  append(attributed, mesh.uv_indices);
  append(attributed, mesh.normals);
  append(attributed, mesh.normal_indices);
  append(attributed, mesh.colors);
  append(attributed, mesh.face_materials);

  pm::ProgressiveMesh progressive;
  if (pm::Status s = pm::encode(mesh, pm::EncodeOptions{}, progressive); !s) die("encode: " + s.message());
  const std::size_t lossless = pm_size(progressive, 0, 0, 0);
  const std::size_t q14 = pm_size(progressive, 14, 10, 8);
  // pmenc --layered: each chunk's splits in layers of independent splits (smaller; levels
  // inside a chunk coarser than the greedy order's); --layer-window 0: the greedy order.
  pm::EncodeOptions layered_options;
  layered_options.layer_window = INFINITY;
  pm::ProgressiveMesh layered;
  if (pm::Status s = pm::encode(mesh, layered_options, layered); !s) die("encode: " + s.message());
  const std::size_t q14_layered = pm_size(layered, 14, 10, 8);
  pm::EncodeOptions greedy_options;
  greedy_options.layer_window = 0;
  pm::ProgressiveMesh greedy;
  if (pm::Status s = pm::encode(mesh, greedy_options, greedy); !s) die("encode: " + s.message());
  const std::size_t q14_greedy = pm_size(greedy, 14, 10, 8);
  const bool attributes = mesh.has_uvs() || mesh.has_normals() || mesh.has_colors() || mesh.has_materials();
  long long geometry_only = -1;
  if (attributes) {
    pm::EncodeOptions options;
    options.drop_attributes = true;
    pm::ProgressiveMesh geometry_pm;
    if (pm::Status s = pm::encode(mesh, options, geometry_pm); !s) die("encode: " + s.message());
    geometry_only = static_cast<long long>(pm_size(geometry_pm, 0, 0, 0));
  }

  const std::string stem = work + "/" + std::filesystem::path(path).stem().string();
  const std::string om = stem + ".om.pm", drc = stem + ".drc";
  std::filesystem::remove(om);
  std::filesystem::remove(drc);
  const std::string quiet = " >/dev/null 2>&1";
  std::system(("OpenMesh-mkbalancedpm -o '" + om + "' '" + path + "'" + quiet).c_str());
  // draco_encoder reads OBJ and PLY: other formats go through pm's PLY writer.
  std::string draco_input = path;
  const std::string extension = std::filesystem::path(path).extension().string();
  if (extension != ".obj" && extension != ".ply") {
    draco_input = stem + ".draco-input.ply";
    std::string bytes;
    if (pm::Status s = pm::write_mesh_to_memory(mesh, pm::MeshFormat::kPly, bytes); !s) die(s.message());
    std::FILE* file = std::fopen(draco_input.c_str(), "wb");
    if (file == nullptr || std::fwrite(bytes.data(), 1, bytes.size(), file) != bytes.size()) die("cannot write " + draco_input);
    std::fclose(file);
  }
  std::system(("draco_encoder -i '" + draco_input + "' -o '" + drc + "' -qp 14 -cl 10" + quiet).c_str());

  const double vertices = static_cast<double>(mesh.vertex_count());
  const auto cell = [&](long long bytes) {
    char text[64];
    if (bytes < 0) return std::string("n/a");
    std::snprintf(text, sizeof text, "%lld (%.1f)", bytes, 8.0 * double(bytes) / vertices);
    return std::string(text);
  };
  const auto ratio = [](long long a, long long b) {
    char text[32];
    if (a < 0 || b <= 0) return std::string("n/a");
    std::snprintf(text, sizeof text, "%.2f", double(a) / double(b));
    return std::string(text);
  };
  const long long raw = static_cast<long long>(zstd19(geometry));
  const long long raw_all = attributes ? static_cast<long long>(zstd19(attributed)) : raw;
  const long long om_size = file_size(om), drc_size = file_size(drc);
  std::printf(
      "| %s | %zu | %zu | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s "
      "| %s |\n",
      std::filesystem::path(path).filename().c_str(), mesh.vertex_count(), mesh.face_count(),
      cell(raw).c_str(), attributes ? cell(raw_all).c_str() : "(same)", cell(om_size).c_str(),
      cell(static_cast<long long>(lossless)).c_str(),
      ratio(static_cast<long long>(lossless), raw_all).c_str(),
      ratio(static_cast<long long>(lossless), om_size).c_str(),
      attributes ? cell(geometry_only).c_str() : "(same)",
      ratio(attributes ? geometry_only : static_cast<long long>(lossless), om_size).c_str(),
      cell(drc_size).c_str(), cell(static_cast<long long>(q14)).c_str(),
      ratio(static_cast<long long>(q14), drc_size).c_str(),
      cell(static_cast<long long>(q14_layered)).c_str(),
      ratio(static_cast<long long>(q14_layered), drc_size).c_str(),
      cell(static_cast<long long>(q14_greedy)).c_str(),
      ratio(static_cast<long long>(q14_greedy), drc_size).c_str(), attributes ? "yes" : "no");
  return 0;
}
