// Timing of pm::measure_surface_distance (issue 3: seconds, not minutes, on a 1M-face mesh).
//
// Prints a markdown table: nefertiti against its 50%, 10% and 2% levels of detail, and
// nefertiti Loop-subdivided twice (about 1.6M faces) against its 10% and 50% levels. Each
// time is the median of --runs measurements with --threads threads, wall clock and CPU time
// of the process (all threads; on a shared machine the wall clock includes the neighbours).
// The Hausdorff and RMS columns are printed to 17 digits, so that two builds can be checked
// for identical results.
//
//   pm_bench_distance [--meshes DIR] [--threads N] [--runs N] [--cache DIR] [--quick]
//
// --cache DIR keeps the subdivided mesh and every level of detail in DIR as binary PLY
// (float32, so exact), since encoding 1.6M faces takes a while; --quick skips the big mesh.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/mesh_io.h"
#include "pm/surface_distance.h"

namespace {

[[noreturn]] void die(const std::string& what, const pm::Status& status) {
  std::fprintf(stderr, "pm_bench_distance: %s: %s\n", what.c_str(), status.message().c_str());
  std::exit(1);
}

pm::Mesh read_or_die(const std::string& path) {
  pm::Mesh mesh;
  if (pm::Status s = pm::read_mesh(path, mesh); !s) die(path, s);
  return mesh;
}

bool file_exists(const std::string& path) {
  return std::ifstream(path).good();
}

void write_or_die(const pm::Mesh& mesh, const std::string& path) {
  std::string bytes;
  if (pm::Status s = pm::write_mesh_to_memory(mesh, pm::MeshFormat::kPly, bytes); !s) die(path, s);
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  if (!out) {
    std::fprintf(stderr, "pm_bench_distance: cannot write %s\n", path.c_str());
    std::exit(1);
  }
}

// One step of Loop subdivision (Loop 1987, "Smooth subdivision surfaces based on
// triangles"): each triangle into four, new edge points at 3/8, 3/8, 1/8, 1/8 of the edge's
// ends and opposite corners, old vertices moved by Warren's weights (beta = 3/16 at valence
// 3, 3/(8n) otherwise). Boundary and non-manifold edges are cut at their midpoint and their
// vertices kept in place, which is enough for a test mesh. Smooth rather than flat, so that
// the levels of detail of the result are not trivially exact.
pm::Mesh loop_subdivide(const pm::Mesh& mesh) {
  struct Edge {
    uint32_t midpoint = 0;
    uint32_t faces = 0;
    double opposite[3] = {0, 0, 0};  // sum of the opposite corners
  };
  const std::size_t vertex_count = mesh.vertex_count();
  auto position = [&](uint32_t v, int axis) { return double(mesh.positions[3 * v + axis]); };
  auto key = [](uint32_t a, uint32_t b) {
    return (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
  };
  std::unordered_map<uint64_t, Edge> edges;
  edges.reserve(mesh.triangles.size());
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const uint32_t a = mesh.triangles[3 * f + c], b = mesh.triangles[3 * f + (c + 1) % 3];
      const uint32_t o = mesh.triangles[3 * f + (c + 2) % 3];
      Edge& edge = edges[key(a, b)];
      ++edge.faces;
      for (int axis = 0; axis < 3; ++axis) edge.opposite[axis] += position(o, axis);
    }
  }
  // Old vertices: the sum and count of their neighbours over interior edges; a vertex on a
  // boundary or non-manifold edge stays where it is.
  std::vector<std::array<double, 3>> neighbour_sum(vertex_count, {0, 0, 0});
  std::vector<uint32_t> valence(vertex_count, 0);
  std::vector<bool> fixed(vertex_count, false);
  pm::Mesh out;
  out.positions.resize(3 * vertex_count);
  uint32_t next = uint32_t(vertex_count);
  for (auto& [k, edge] : edges) {
    const auto a = uint32_t(k >> 32), b = uint32_t(k & 0xffffffffu);
    edge.midpoint = next++;
    for (int axis = 0; axis < 3; ++axis) {
      const double ends = position(a, axis) + position(b, axis);
      const double p = edge.faces == 2 ? 0.375 * ends + 0.125 * edge.opposite[axis] : 0.5 * ends;
      out.positions.push_back(float(p));
      neighbour_sum[a][axis] += position(b, axis);
      neighbour_sum[b][axis] += position(a, axis);
    }
    ++valence[a];
    ++valence[b];
    if (edge.faces != 2) fixed[a] = fixed[b] = true;
  }
  for (uint32_t v = 0; v < vertex_count; ++v) {
    const double n = valence[v];
    const double beta = n == 3 ? 3.0 / 16 : 3.0 / (8 * n);
    for (int axis = 0; axis < 3; ++axis) {
      const double p = fixed[v] || n == 0
                           ? position(v, axis)
                           : (1 - n * beta) * position(v, axis) + beta * neighbour_sum[v][axis];
      out.positions[3 * v + axis] = float(p);
    }
  }
  out.triangles.reserve(4 * mesh.triangles.size());
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const uint32_t* t = &mesh.triangles[3 * f];
    const uint32_t ab = edges[key(t[0], t[1])].midpoint, bc = edges[key(t[1], t[2])].midpoint,
                   ca = edges[key(t[2], t[0])].midpoint;
    out.triangles.insert(out.triangles.end(),
                         {t[0], ab, ca, t[1], bc, ab, t[2], ca, bc, ab, bc, ca});
  }
  return out;
}

// The levels of detail of `mesh` with the given fractions of its faces, as pmdec --ratio
// picks them; read from the cache when there.
std::vector<pm::Mesh> levels_of_detail(const pm::Mesh& mesh, const std::string& name,
                                       const std::vector<double>& ratios,
                                       const std::string& cache) {
  std::vector<pm::Mesh> levels(ratios.size());
  std::vector<std::string> paths(ratios.size());
  bool all_cached = !cache.empty();
  for (std::size_t i = 0; i < ratios.size(); ++i) {
    if (cache.empty()) break;
    paths[i] = cache + "/" + name + "-" + std::to_string(int(std::lround(ratios[i] * 1000))) +
               "permille.ply";
    all_cached = all_cached && file_exists(paths[i]);
  }
  if (all_cached) {
    for (std::size_t i = 0; i < ratios.size(); ++i) levels[i] = read_or_die(paths[i]);
    return levels;
  }
  std::fprintf(stderr, "encoding %s (%zu faces)...\n", name.c_str(), mesh.face_count());
  pm::ProgressiveMesh progressive;
  if (pm::Status s = pm::encode(mesh, {}, progressive); !s) die("encoding " + name, s);
  const std::size_t full = pm::faces_at_level(progressive, progressive.splits.size());
  for (std::size_t i = 0; i < ratios.size(); ++i) {
    const auto wanted = std::size_t(std::llround(ratios[i] * double(full)));
    levels[i] = pm::extract_level(progressive, pm::level_for_faces(progressive, wanted));
    if (!cache.empty()) write_or_die(levels[i], paths[i]);
  }
  return levels;
}

struct Row {
  std::string mesh;
  std::size_t faces = 0, lod_faces = 0, samples = 0;
  double seconds = 0, cpu_seconds = 0, hausdorff = 0, rms = 0;
};

// CPU time of the whole process, all threads: on a shared machine, the wall-clock time
// says as much about the neighbours as about the code.
double process_cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

Row time_distance(const std::string& name, const pm::Mesh& reference, const pm::Mesh& lod,
                  unsigned threads, int runs) {
  pm::DistanceOptions options;
  options.threads = threads;
  std::vector<double> seconds, cpu_seconds;
  pm::SurfaceDistance distance;
  for (int run = 0; run < runs; ++run) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = process_cpu_seconds();
    if (pm::Status s = pm::measure_surface_distance(reference, lod, options, distance); !s)
      die(name, s);
    cpu_seconds.push_back(process_cpu_seconds() - cpu_start);
    seconds.push_back(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(seconds.begin(), seconds.end());
  std::sort(cpu_seconds.begin(), cpu_seconds.end());
  Row row;
  row.mesh = name;
  row.faces = reference.face_count();
  row.lod_faces = lod.face_count();
  row.samples = distance.samples;
  row.seconds = seconds[seconds.size() / 2];
  row.cpu_seconds = cpu_seconds[cpu_seconds.size() / 2];
  row.hausdorff = distance.hausdorff;
  row.rms = distance.rms;
  return row;
}

std::string cpu_name() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(colon + 2);
    }
  }
  return "unknown CPU";
}

}  // namespace

int main(int argc, char** argv) {
  std::string meshes = "../shared/meshes", cache;
  unsigned threads = 2;
  int runs = 5;
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--meshes" && has_value) {
      meshes = argv[++i];
    } else if (arg == "--threads" && has_value) {
      threads = unsigned(std::atoi(argv[++i]));
    } else if (arg == "--runs" && has_value) {
      runs = std::max(1, std::atoi(argv[++i]));
    } else if (arg == "--cache" && has_value) {
      cache = argv[++i];
    } else if (arg == "--quick") {
      quick = true;
    } else {
      std::fprintf(stderr,
                   "usage: pm_bench_distance [--meshes DIR] [--threads N] [--runs N] "
                   "[--cache DIR] [--quick]\n");
      return 2;
    }
  }

  std::vector<Row> rows;
  const pm::Mesh nefertiti = read_or_die(meshes + "/nefertiti.obj");
  const std::vector<double> ratios = {0.5, 0.1, 0.02};
  const std::vector<pm::Mesh> nefertiti_levels =
      levels_of_detail(nefertiti, "nefertiti", ratios, cache);
  for (std::size_t i = 0; i < ratios.size(); ++i) {
    rows.push_back(time_distance("nefertiti", nefertiti, nefertiti_levels[i], threads, runs));
  }
  if (!quick) {
    pm::Mesh fine;
    const std::string fine_path = cache.empty() ? "" : cache + "/nefertiti-loop2.ply";
    if (!fine_path.empty() && file_exists(fine_path)) {
      fine = read_or_die(fine_path);
    } else {
      fine = loop_subdivide(loop_subdivide(nefertiti));
      if (!fine_path.empty()) write_or_die(fine, fine_path);
    }
    const std::vector<pm::Mesh> fine_levels =
        levels_of_detail(fine, "nefertiti-loop2", {0.1, 0.5}, cache);
    for (const pm::Mesh& level : fine_levels)
      rows.push_back(time_distance("nefertiti, Loop x2", fine, level, threads, runs));
  }

  char date[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  std::printf("## measure_surface_distance: %s, %u hardware threads, %u threads used, %s\n\n",
              cpu_name().c_str(), std::thread::hardware_concurrency(), threads, date);
  std::printf(
      "| mesh | faces | LOD faces | samples | seconds (median of %d) | samples/s | "
      "CPU seconds | hausdorff | rms |\n",
      runs);
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const Row& row : rows) {
    std::printf("| %s | %zu | %zu | %zu | %.3f | %.3g | %.3f | %.17g | %.17g |\n", row.mesh.c_str(),
                row.faces, row.lod_faces, row.samples, row.seconds,
                double(row.samples) / row.seconds, row.cpu_seconds, row.hausdorff, row.rms);
  }
  return 0;
}
