// pm_bench_decode: the decode part of issue 10. On the large meshes (Loop subdivision of
// the shared meshes, big_mesh.h) it times a full decode, from the stream's bytes in memory to
// the full-detail mesh, in the same run and side by side:
//
//   ours         pm::read_pm of the stream pmenc writes (lossless, at pmenc's default zstd level), then
//                pm::extract_level at full detail: a pm::Mesh, as pmdec makes before writing
//   ours q14     the same progressive mesh written with 14-bit positions (pmenc --quantize 14)
//   OpenMesh     its own .pm (ModProgMeshT's file): parsed, the base mesh loaded into a TriMesh
//                and every record replayed with TriMesh::vertex_split, as its ProgViewer does
//   Draco        draco::Decoder::DecodeMeshFromBuffer of `draco_encoder -qp 14 -cl 10` of the
//                same mesh (one level of detail only)
//
// Splits per second divide the stream's vertex splits by the whole decode's time (the base
// mesh, the decompression and the replay): what a user waits for. Faces per second divide
// the full mesh's faces by it, the measure Draco is quoted in.
//
//   pm_bench_decode [--mesh FILE:STEPS]... [--runs N] [--cache DIR] [--out FILE]
//
// Default meshes: nefertiti after 2 Loop steps (1.6M faces); tests/bench/run_decode.sh --big
// adds the bunny after 3 (4.4M). Every timing is the median of --runs runs (at least 5), the
// four decoders interleaved in each run so that a change in the machine's load hits all
// alike. Both progressive meshes are encoded once and cached (progressive_setups.h).
#include <draco/compression/decode.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench_report.h"
#include "big_mesh.h"
#include "pm/lod.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "progressive_setups.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using pm::bench::fail;
using pm::bench::OMesh;
using pm::bench::median;
using pm::bench::significant;
using pm::bench::with_thousands;

struct MeshSpec {
  std::string path;
  int steps = 2;
};

struct Settings {
  std::vector<MeshSpec> meshes;
  int runs = 7;
  std::string cache = pm::bench::default_cache_dir();
  std::string out;
};

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

struct Decoder {
  std::string name;
  std::string stream;  // what it decodes
  std::size_t bytes = 0;
  std::size_t splits = 0;  // 0: a single-resolution decoder
  std::size_t faces = 0;   // at full detail, checked after every run
  std::vector<double> seconds;
  // Ours only: the two calls apart.
  std::vector<double> read_seconds, extract_seconds;
  double time() const { return median(seconds); }
};

struct MeshReport {
  std::string name;
  std::size_t faces = 0, vertices = 0;
  std::vector<Decoder> decoders;  // ours, ours q14, OpenMesh, Draco
};

// `draco_encoder -qp 14 -cl 10` of the mesh, as the size benchmark runs it (its defaults
// for the rest), through a binary PLY that pm writes.
std::string draco_stream(const pm::Mesh& mesh, const std::string& work) {
  const std::string ply = work + "/draco-input.ply", drc = work + "/draco.drc";
  std::string ply_bytes;
  if (pm::Status s = pm::write_mesh_to_memory(mesh, pm::MeshFormat::kPly, ply_bytes);
      !s || !pm::bench::write_file_atomically(ply, ply_bytes))
    fail("cannot write " + ply);
  const std::string command = "draco_encoder -i " + pm::bench::shell_quoted(ply) + " -o " +
                              pm::bench::shell_quoted(drc) + " -qp 14 -cl 10 >/dev/null 2>&1";
  if (std::system(command.c_str()) != 0)
    fail("draco_encoder failed (apt-get install draco; run_decode.sh installs it)");
  std::string bytes;
  if (!pm::bench::read_file(drc, bytes)) fail("cannot read " + drc);
  fs::remove(ply);
  fs::remove(drc);
  return bytes;
}

MeshReport run_mesh(const MeshSpec& spec, const Settings& settings) {
  MeshReport report;
  pm::Mesh input;
  if (pm::Status s = pm::bench::load_subdivided(spec.path, spec.steps, settings.cache, input); !s)
    fail(spec.path + ": " + s.message());
  report.name = fs::path(spec.path).filename().string() + " after " + std::to_string(spec.steps) +
                " Loop steps";
  report.faces = input.face_count();
  report.vertices = input.vertex_count();
  const std::string name = fs::path(spec.path).stem().string() + "-loop" + std::to_string(spec.steps);

  pm::bench::OurSetup our_setup;
  const pm::ProgressiveMesh progressive =
      pm::bench::our_progressive_mesh(input, name, settings.cache, our_setup);
  pm::bench::OpenMeshSetup om_setup;
  const pm::bench::OpenMeshPm om_parsed =
      pm::bench::openmesh_progressive_mesh(input, name, settings.cache, om_setup);

  auto decoder = [](const char* name, const char* stream) {
    Decoder d;
    d.name = name;
    d.stream = stream;
    return d;
  };
  Decoder ours = decoder("**ours** (`read_pm` + `extract_level`, lossless)", "pmenc's .pm, lossless");
  Decoder ours_q14 = decoder("**ours q14** (the same, 14-bit positions)", "pmenc --quantize 14");
  Decoder openmesh =
      decoder("OpenMesh (parse, load the base, `vertex_split` per record)", "ModProgMeshT's .pm");
  Decoder draco = decoder("Draco (`DecodeMeshFromBuffer`)", "draco_encoder -qp 14 -cl 10");
  std::string our_bytes, q14_bytes, om_bytes;
  if (pm::Status s = pm::write_pm(progressive, pm::WriteOptions{}, our_bytes); !s)
    fail("write_pm: " + s.message());
  pm::WriteOptions q14_options;
  q14_options.position_bits = 14;
  if (pm::Status s = pm::write_pm(progressive, q14_options, q14_bytes); !s)
    fail("write_pm --quantize 14: " + s.message());
  if (!pm::bench::read_file(om_setup.path, om_bytes)) fail("cannot read " + om_setup.path);
  const std::string draco_bytes = draco_stream(input, settings.cache);
  input = pm::Mesh();  // the decoders get the memory

  ours.bytes = our_bytes.size();
  ours_q14.bytes = q14_bytes.size();
  openmesh.bytes = om_bytes.size();
  draco.bytes = draco_bytes.size();
  ours.splits = ours_q14.splits = progressive.split_count();
  openmesh.splits = om_parsed.records.size();

  auto decode_ours = [&](const std::string& bytes, Decoder& d) {
    const auto start = Clock::now();
    pm::ProgressiveMesh pm;
    if (pm::Status s = pm::read_pm(bytes, pm); !s) fail("read_pm: " + s.message());
    const auto read = Clock::now();
    const pm::Mesh full = pm::extract_level(pm, pm.split_count());
    const auto end = Clock::now();
    d.seconds.push_back(std::chrono::duration<double>(end - start).count());
    d.read_seconds.push_back(std::chrono::duration<double>(read - start).count());
    d.extract_seconds.push_back(std::chrono::duration<double>(end - read).count());
    d.faces = full.face_count();
  };
  for (int r = 0; r < settings.runs; ++r) {
    std::fprintf(stderr, "[decode] %s: run %d of %d\n", name.c_str(), r + 1, settings.runs);
    decode_ours(our_bytes, ours);
    decode_ours(q14_bytes, ours_q14);
    {
      const auto start = Clock::now();
      pm::bench::OpenMeshPm om;
      std::string problem;
      if (!pm::bench::parse_openmesh_pm(om_bytes, om, problem)) fail("OpenMesh's .pm: " + problem);
      OMesh mesh;
      pm::bench::load_base(om, mesh);
      for (const auto& rec : om.records)
        mesh.vertex_split(rec.p0, OMesh::VertexHandle(rec.v1), OMesh::VertexHandle(rec.vl),
                          OMesh::VertexHandle(rec.vr));
      openmesh.seconds.push_back(seconds_since(start));
      openmesh.faces = mesh.n_faces();
    }
    {
      const auto start = Clock::now();
      draco::DecoderBuffer buffer;
      buffer.Init(draco_bytes.data(), draco_bytes.size());
      draco::Decoder decoder;
      auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
      if (!decoded.ok()) fail(std::string("Draco: ") + decoded.status().error_msg());
      draco.seconds.push_back(seconds_since(start));
      draco.faces = decoded.value()->num_faces();
    }
  }
  for (const Decoder* d : {&ours, &ours_q14, &openmesh, &draco})
    if (d->faces != report.faces)
      fail(d->name + " decoded " + std::to_string(d->faces) + " faces, not " +
           std::to_string(report.faces));
  report.decoders = {ours, ours_q14, openmesh, draco};
  return report;
}

std::string rate(double per_second) { return with_thousands(std::size_t(per_second + 0.5)); }

std::string render(const std::vector<MeshReport>& reports, const Settings& settings,
                   const std::string& load) {
  std::ostringstream md;
  md << "# Decode benchmark\n\n"
     << "Issue 10's decode rows: a full decode, from the stream's bytes in memory to the "
        "full-detail mesh, ours beside OpenMesh's progressive-mesh replay and Draco's decoder, "
        "in one run. Regenerate with `bash tests/bench/run_decode.sh` (`--big` adds the "
        "4.4M-face mesh); see tests/bench/README.md, \"Decode\".\n\n"
     << pm::bench::run_description(PM_BENCH_SOURCE_DIR)
     << "- load average at the start (1, 5, 15 min): " << load
     << " (a shared machine: the neighbours' work is in every time)\n"
     << "- peers: OpenMesh " << pm::bench::command_output("dpkg-query -W -f='${Version}' libopenmesh-dev 2>/dev/null")
     << ", Draco " << pm::bench::command_output("dpkg-query -W -f='${Version}' libdraco-dev 2>/dev/null")
     << "\n- every time: the median of " << settings.runs
     << " runs, the four decoders interleaved in each run\n\n";
  std::vector<std::string> verdicts;
  for (const MeshReport& r : reports) {
    md << "## " << r.name << ": " << with_thousands(r.faces) << " faces, "
       << with_thousands(r.vertices) << " vertices\n\n"
       << "| decoder | stream | bytes | time (ms) | vertex splits per second | faces per second | ours / this (time) | ours q14 / this (time) |\n"
       << "|---|---|---:|---:|---:|---:|---:|---:|\n";
    const Decoder& ours = r.decoders[0];
    const Decoder& q14 = r.decoders[1];
    for (const Decoder& d : r.decoders) {
      md << "| " << d.name << " | " << d.stream << " | " << with_thousands(d.bytes) << " | "
         << significant(1e3 * d.time()) << " | "
         << (d.splits ? rate(double(d.splits) / d.time()) : std::string("(one level)")) << " | "
         << rate(double(d.faces) / d.time()) << " | " << significant(ours.time() / d.time())
         << "× | " << significant(q14.time() / d.time()) << "× |\n";
    }
    const Decoder& om = r.decoders[2];
    const Decoder& draco = r.decoders[3];
    const double split_ratio = (double(ours.splits) / ours.time()) / (double(om.splits) / om.time());
    const double draco_ratio = draco.time() / q14.time();
    // Where our time goes, and what the goals leave: 20 times OpenMesh's rate is OpenMesh's
    // time / 20 for our splits; Draco's is its time.
    md << "\nWhere our time goes (medians of the same runs):\n\n"
       << "| stream | read_pm (ms) | extract_level (ms) | ns per split, all | "
          "20× OpenMesh leaves (ms) | Draco's time (ms) |\n"
       << "|---|---:|---:|---:|---:|---:|\n";
    const double openmesh_goal = om.time() / 20 * double(ours.splits) / double(om.splits);
    for (const Decoder* d : {&ours, &q14}) {
      md << "| " << d->stream << " | " << significant(1e3 * median(d->read_seconds)) << " | "
         << significant(1e3 * median(d->extract_seconds)) << " | "
         << significant(1e9 * d->time() / double(d->splits)) << " | "
         << significant(1e3 * openmesh_goal) << " | " << significant(1e3 * draco.time()) << " |\n";
    }
    md << "\n";
    verdicts.push_back("| " + r.name + " | " + significant(split_ratio) + "× | " +
                       (split_ratio >= 20 ? "holds" : "**does not hold**") + " | " +
                       significant(draco_ratio) + "× | " +
                       (draco_ratio >= 1 ? "holds" : "**does not hold**") + " |");
  }
  md << "## Summary\n\n"
     << "Issue 10: full decode at least 20 times the vertex splits per second of OpenMesh's "
        "replay, and not slower than Draco's decode of the same mesh at 14-bit quantization "
        "(ours at 14 bits: Draco's time / ours).\n\n"
     << "| mesh | ours / OpenMesh, splits per second | ≥ 20× | ours q14 / Draco, speed | ≥ 1× |\n"
     << "|---|---:|---|---:|---|\n";
  for (const std::string& v : verdicts) md << v << "\n";
  return md.str();
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--mesh" && has_value) {
      const std::string value = argv[++i];
      const std::size_t colon = value.rfind(':');
      MeshSpec spec{value, 2};
      if (colon != std::string::npos) {
        spec.path = value.substr(0, colon);
        spec.steps = std::atoi(value.c_str() + colon + 1);
      }
      if (spec.steps < 0 || spec.steps > 4) fail("--mesh FILE:STEPS: steps must be 0 to 4");
      settings.meshes.push_back(spec);
    } else if (arg == "--runs" && has_value) {
      settings.runs = std::max(5, std::atoi(argv[++i]));
    } else if (arg == "--cache" && has_value) {
      settings.cache = argv[++i];
    } else if (arg == "--out" && has_value) {
      settings.out = argv[++i];
    } else {
      std::fprintf(stderr,
                   "usage: pm_bench_decode [--mesh FILE:STEPS]... [--runs N (>= 5)] [--cache DIR] "
                   "[--out FILE]\n"
                   "  Full decode of ours, OpenMesh's .pm replay and Draco on FILE after STEPS Loop\n"
                   "  steps (default %s/nefertiti.obj:2).\n",
                   pm::bench::shared_meshes_dir().c_str());
      return 2;
    }
  }
  if (settings.meshes.empty())
    settings.meshes.push_back({pm::bench::shared_meshes_dir() + "/nefertiti.obj", 2});
  const std::string load = pm::bench::command_output("cut -d' ' -f1-3 /proc/loadavg 2>/dev/null");
  std::vector<MeshReport> reports;
  for (const MeshSpec& spec : settings.meshes) reports.push_back(run_mesh(spec, settings));
  const std::string md = render(reports, settings, load);
  std::fputs(md.c_str(), stdout);
  if (!settings.out.empty() && !pm::bench::write_file_atomically(settings.out, md))
    fail("cannot write " + settings.out);
  return 0;
}
