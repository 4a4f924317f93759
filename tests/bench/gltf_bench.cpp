// The glTF chain's bytes (issue 29): a model's levels written as ONE file sharing one vertex
// buffer (pmdec --lods ... -o model.glb) against the same levels written as separate meshes,
// one file each with its own vertices (gltfpack's way: one level per run). Both plain floats
// and KHR_mesh_quantization (pmdec --quantize). Prints a markdown table.
//
//   pm_bench_gltf OUTPUT.md MESH...
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "bench_report.h"
#include "pm/encoder.h"
#include "pm/gltf.h"
#include "pm/lod.h"
#include "pm/mesh_io.h"

namespace {

// pmdec --lods 100%,50%,25%,12.5%, coarse to fine.
constexpr double kShares[] = {0.125, 0.25, 0.5, 1.0};

std::size_t glb_bytes(const std::vector<pm::GltfLevel>& levels, bool quantize) {
  pm::GltfWriteOptions options;
  options.quantize = quantize;
  std::string bytes;
  if (!pm::write_gltf(levels, options, bytes)) return 0;
  return bytes.size();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: pm_bench_gltf OUTPUT.md MESH...\n");
    return 2;
  }
  std::string table =
      "| mesh | faces per level | chain (one file) | separate files | chain / separate | chain, quantized | "
      "separate, quantized | chain / separate |\n|---|---|---:|---:|---:|---:|---:|---:|\n";
  for (int i = 2; i < argc; ++i) {
    pm::Mesh mesh;
    if (pm::Status s = pm::read_mesh(argv[i], mesh); !s) {
      std::fprintf(stderr, "%s: %s\n", argv[i], s.message().c_str());
      return 1;
    }
    pm::ProgressiveMesh progressive;
    if (pm::Status s = pm::encode(mesh, {}, progressive); !s) {
      std::fprintf(stderr, "%s: %s\n", argv[i], s.message().c_str());
      return 1;
    }
    const std::size_t full = pm::faces_at_level(progressive, progressive.split_count());
    std::vector<std::size_t> wanted;
    for (double share : kShares) wanted.push_back(pm::level_for_faces(progressive, std::size_t(share * full + 0.5)));
    std::vector<pm::Mesh> meshes;
    pm::extract_levels(progressive, wanted, [&](std::size_t, const pm::Mesh& m) {
      meshes.push_back(m);
      pm::group_faces_by_material(meshes.back());
    });
    std::vector<pm::GltfLevel> levels;
    std::string faces;
    for (std::size_t k = 0; k < meshes.size(); ++k) {
      levels.push_back({&meshes[k], pm::error_at_level(progressive, wanted[k])});
      faces = pm::bench::with_thousands(meshes[k].face_count()) + (k ? ", " : "") + faces;
    }
    std::size_t separate[2] = {0, 0}, chain[2] = {0, 0};
    for (int q = 0; q < 2; ++q) {
      chain[q] = glb_bytes(levels, q);
      for (const pm::GltfLevel& level : levels) separate[q] += glb_bytes({level}, q);
    }
    std::string name = argv[i];
    name = name.substr(name.find_last_of('/') + 1);
    table += "| " + name + " | " + faces + " | " + pm::bench::with_thousands(chain[0]) + " | " +
             pm::bench::with_thousands(separate[0]) + " | " + pm::bench::significant(double(chain[0]) / separate[0]) +
             " | " + pm::bench::with_thousands(chain[1]) + " | " + pm::bench::with_thousands(separate[1]) + " | " +
             pm::bench::significant(double(chain[1]) / separate[1]) + " |\n";
  }
  const std::string report =
      "# glTF: a chain of levels in one file against separate files\n\n"
      "Made by `bash tests/bench/run_gltf.sh` (pm_bench_gltf, tests/bench/gltf_bench.cpp). Each mesh "
      "is encoded with pmenc's defaults and decoded at 100%, 50%, 25% and 12.5% of its faces (pmdec "
      "--lods 100%,50%,25%,12.5%). *Chain*: the four levels in one .glb, one vertex buffer shared by "
      "all (vertices in the order the levels first use them, coarse to fine), one index buffer per "
      "level, MSFT_lod. *Separate*: each level in its own .glb with its own vertices, as gltfpack "
      "writes levels (one per run); the sum of the four. Bytes of the files; *quantized* is "
      "KHR_mesh_quantization (pmdec --quantize: 16-bit positions, 8-bit normals, 16-bit texture "
      "coordinates in [0, 1]).\n\n" +
      pm::bench::run_description(PM_BENCH_SOURCE_DIR) + "\n" + table;
  std::ofstream(argv[1]) << report;
  std::fputs(report.c_str(), stdout);
  return 0;
}
