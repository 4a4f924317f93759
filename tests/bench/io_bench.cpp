// pm_bench_io: mesh reading and writing throughput (issue 10), pm's own readers and writers
// against OpenMesh's IO in the same process, on the same files:
//
//   read OBJ    pm::read_mesh(MESH.obj)                 OpenMesh::IO::read_mesh(TriMesh, MESH.obj)
//   read PLY    pm::read_mesh(MESH.ply)                 OpenMesh::IO::read_mesh(TriMesh, MESH.ply)
//   write OBJ   pm::write_mesh_to_memory + one fwrite   OpenMesh::IO::write_mesh(TriMesh, .obj,
//                                                       precision 9, and its default 6)
//   write PLY   pm::write_mesh_to_memory + one fwrite   OpenMesh::IO::write_mesh(TriMesh, .ply,
//                                                       Options::Binary)
//
// MESH.ply is the input written by pm's PLY writer (binary little-endian), which both read.
// OpenMesh's TriMesh is the one its own reader made from MESH.obj, so both writers get the
// same positions and faces. Every timing is the median of --runs runs (at least 5), ours and
// OpenMesh's interleaved in each run so that a change in the machine's load hits both alike.
// A read is from the page cache (the file was read just before); a write ends when the data
// is in the page cache (no fsync), as for any program writing a file.
//
//   pm_bench_io MESH.obj [MESH.obj...] [--runs N] [--work DIR] [--out FILE]
//
// Markdown sections on stdout (and appended to --out FILE), one per mesh; progress on
// stderr. run_io.sh writes the page's header. See README.md here, "Reading and writing".
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "bench_report.h"
#include "pm/mesh_io.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;
using pm::bench::median;
using pm::bench::significant;
using pm::bench::with_thousands;

struct Settings {
  std::vector<std::string> meshes;
  int runs = 7;
  std::string work = fs::temp_directory_path() / "pm_bench_io";
  std::string out;
};

[[noreturn]] void die(const std::string& message) {
  std::fprintf(stderr, "pm_bench_io: %s\n", message.c_str());
  std::exit(1);
}

double time_once(const std::function<void()>& work) {
  const Clock::time_point start = Clock::now();
  work();
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::size_t file_size(const std::string& path) {
  std::error_code error;
  const auto size = fs::file_size(path, error);
  if (error) die("cannot stat " + path);
  return static_cast<std::size_t>(size);
}

// Ours, as a program writes a file: the bytes in memory, then one write.
void write_ours(const pm::Mesh& mesh, pm::MeshFormat format, const std::string& path) {
  std::string bytes;
  if (pm::Status s = pm::write_mesh_to_memory(mesh, format, bytes); !s)
    die(path + ": " + s.message());
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) die("cannot write " + path);
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
  if (std::fclose(file) != 0 || !ok) die("cannot write " + path);
}

void read_ours(const std::string& path, pm::Mesh& mesh) {
  if (pm::Status s = pm::read_mesh(path, mesh); !s) die(path + ": " + s.message());
}

void read_openmesh(const std::string& path, OMesh& mesh) {
  mesh.clear();
  mesh.garbage_collection();
  if (!OpenMesh::IO::read_mesh(mesh, path)) die("OpenMesh cannot read " + path);
}

// One row: the medians of both sides and the bytes each moved.
struct Row {
  std::string what;
  std::string peer;  // how OpenMesh was called
  double ours_s = 0, peer_s = 0;
  std::size_t ours_bytes = 0, peer_bytes = 0;
};

std::string mb_per_s(std::size_t bytes, double seconds) {
  return significant(static_cast<double>(bytes) / 1e6 / seconds);
}

std::string report_mesh(const std::string& obj, const Settings& settings) {
  const std::string name = fs::path(obj).stem().string();
  fs::create_directories(settings.work);
  const std::string base = (fs::path(settings.work) / name).string();
  const std::string ply = base + ".ply";

  // The data both sides write, and the PLY both read.
  pm::Mesh mesh;
  read_ours(obj, mesh);
  write_ours(mesh, pm::MeshFormat::kPly, ply);
  OMesh om;
  read_openmesh(obj, om);
  if (om.n_faces() != mesh.face_count() || om.n_vertices() != mesh.vertex_count())
    die("OpenMesh read " + obj + " as " + std::to_string(om.n_faces()) + " faces, not " +
        std::to_string(mesh.face_count()));

  std::vector<double> t[10];
  pm::Mesh scratch;
  OMesh om_scratch;
  for (int run = 0; run < settings.runs; ++run) {
    std::fprintf(stderr, "pm_bench_io: %s: run %d of %d\n", name.c_str(), run + 1, settings.runs);
    t[0].push_back(time_once([&] { read_ours(obj, scratch); }));
    t[1].push_back(time_once([&] { read_openmesh(obj, om_scratch); }));
    t[2].push_back(time_once([&] { read_ours(ply, scratch); }));
    t[3].push_back(time_once([&] { read_openmesh(ply, om_scratch); }));
    t[4].push_back(time_once([&] { write_ours(mesh, pm::MeshFormat::kObj, base + ".ours.obj"); }));
    t[5].push_back(time_once([&] {
      if (!OpenMesh::IO::write_mesh(om, base + ".om9.obj", OpenMesh::IO::Options::Default, 9))
        die("OpenMesh cannot write " + base + ".om9.obj");
    }));
    t[6].push_back(time_once([&] {
      if (!OpenMesh::IO::write_mesh(om, base + ".om6.obj")) die("OpenMesh cannot write obj");
    }));
    t[7].push_back(time_once([&] { write_ours(mesh, pm::MeshFormat::kPly, base + ".ours.ply"); }));
    t[8].push_back(time_once([&] {
      if (!OpenMesh::IO::write_mesh(om, base + ".om.ply", OpenMesh::IO::Options::Binary))
        die("OpenMesh cannot write " + base + ".om.ply");
    }));
  }
  // What was read is what was written: both sides' outputs hold the mesh (checked once,
  // outside the timings).
  for (const char* suffix : {".ours.obj", ".ours.ply", ".om9.obj", ".om.ply"}) {
    read_ours(base + suffix, scratch);
    if (scratch.face_count() != mesh.face_count())
      die(base + suffix + " holds " + std::to_string(scratch.face_count()) + " faces");
  }
  read_ours(ply, scratch);
  if (scratch.positions != mesh.positions || scratch.triangles != mesh.triangles)
    die(ply + " does not read back as " + obj);
  read_openmesh(ply, om_scratch);
  if (om_scratch.n_faces() != mesh.face_count() || om_scratch.n_vertices() != mesh.vertex_count())
    die("OpenMesh read " + ply + " as " + std::to_string(om_scratch.n_faces()) + " faces");

  const std::size_t obj_bytes = file_size(obj), ply_bytes = file_size(ply);
  const Row rows[] = {
      {"read OBJ", "`read_mesh`", median(t[0]), median(t[1]), obj_bytes, obj_bytes},
      {"read PLY (binary)", "`read_mesh`", median(t[2]), median(t[3]), ply_bytes, ply_bytes},
      {"write OBJ", "`write_mesh`, precision 9 (round trip)", median(t[4]), median(t[5]),
       file_size(base + ".ours.obj"), file_size(base + ".om9.obj")},
      {"write OBJ", "`write_mesh`, default precision 6 (lossy)", median(t[4]), median(t[6]),
       file_size(base + ".ours.obj"), file_size(base + ".om6.obj")},
      {"write PLY (binary)", "`write_mesh`, `Options::Binary`", median(t[7]), median(t[8]),
       file_size(base + ".ours.ply"), file_size(base + ".om.ply")},
  };
  std::string text = "\n## " + name + ": " + with_thousands(mesh.face_count()) + " faces, " +
                     with_thousands(mesh.vertex_count()) + " vertices\n\n";
  text += "OBJ " + significant(static_cast<double>(obj_bytes) / 1e6) + " MB (pm's writer), PLY " +
          significant(static_cast<double>(ply_bytes) / 1e6) + " MB (pm's binary writer); " +
          std::to_string(settings.runs) + " runs, medians.\n\n";
  text +=
      "| operation | OpenMesh call | ours (s) | ours (MB/s) | OpenMesh (s) | OpenMesh (MB/s) | "
      "OpenMesh time / ours |\n|---|---|---:|---:|---:|---:|---:|\n";
  for (const Row& row : rows) {
    text += "| " + row.what + " | " + row.peer + " | " + significant(row.ours_s) + " | " +
            mb_per_s(row.ours_bytes, row.ours_s) + " | " + significant(row.peer_s) + " | " +
            mb_per_s(row.peer_bytes, row.peer_s) + " | " + significant(row.peer_s / row.ours_s) +
            "× |\n";
  }
  for (const char* suffix : {".ply", ".ours.obj", ".ours.ply", ".om9.obj", ".om6.obj", ".om.ply"})
    fs::remove(base + suffix);
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) die(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--runs") {
      settings.runs = std::atoi(value().c_str());
      if (settings.runs < 5) die("--runs must be at least 5 (each row is a median)");
    } else if (arg == "--work") {
      settings.work = value();
    } else if (arg == "--out") {
      settings.out = value();
    } else if (!arg.empty() && arg[0] != '-') {
      settings.meshes.push_back(arg);
    } else {
      die("usage: pm_bench_io MESH.obj [MESH.obj...] [--runs N] [--work DIR] [--out FILE]");
    }
  }
  if (settings.meshes.empty()) die("no mesh given (usage: pm_bench_io MESH.obj ...)");
  // OpenMesh's writers log each file to stderr, between our progress lines.
  omlog().disable();
  omout().disable();
  for (const std::string& mesh : settings.meshes) {
    const std::string text = report_mesh(mesh, settings);
    std::fputs(text.c_str(), stdout);
    std::fflush(stdout);
    if (!settings.out.empty()) {
      std::ofstream out(settings.out, std::ios::app);
      out << text;
      if (!out) die("cannot write " + settings.out);
    }
  }
  return 0;
}
