// pm_bench_runtime: the runtime benchmark of issue 6. On the ~1M-face mesh (the Stanford
// bunny after two steps of Loop subdivision, big_mesh.h) it measures pm::RuntimeLod, the
// in-place refinement and coarsening of Hoppe 1998 ("Efficient implementation of
// progressive meshes", §4-5), beside OpenMesh's own progressive meshes in the same run:
//
//   - vertex splits (and edge collapses) per second from the base mesh to full detail and
//     back, against OpenMesh replaying the .pm its ModProgMeshT writes the way its
//     ProgViewer does (TriMesh::vertex_split per record; find_halfedge, collapse and a
//     garbage collection to coarsen);
//   - the latency of a change of 1% of the faces at 10% and at 100% detail;
//   - the memory per vertex of the runtime object;
//   - the time per frame of a geomorph's evaluation (Hoppe 1996, "Progressive meshes", §4.2).
//
//   pm_bench_runtime [--mesh FILE] [--steps N] [--runs N] [--cache DIR] [--out FILE]
//
// Every timing is the median of --runs runs (at least 5), ours and OpenMesh's interleaved
// in each run so that a change in the machine's load hits both alike. Encoding the mesh
// (both ways) takes minutes, so both .pm files are cached in --cache, keyed by the input's
// content and, for ours, by the library's source. Markdown on stdout (and --out FILE),
// progress on stderr. See README.md here, "Runtime".
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "bench_report.h"
#include "big_mesh.h"
#include "progressive_setups.h"
#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/lod_runtime.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using pm::bench::load_base;
using pm::bench::OMesh;
using pm::bench::OpenMeshPm;
using pm::bench::OpenMeshSetup;
using pm::bench::OurSetup;
using pm::bench::openmesh_progressive_mesh;
using pm::bench::our_progressive_mesh;
using pm::bench::median;
using pm::bench::significant;
using pm::bench::with_thousands;

struct Settings {
  std::string mesh;  // default: the shared bunny
  int steps = 2;     // Loop steps: 4^2 = 16 times the faces
  int runs = 7;
  std::string cache = pm::bench::default_cache_dir();
  std::string out;
};

[[noreturn]] void die(const std::string& message) { pm::bench::fail(message); }

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Nearest rank: the smallest value with at least fraction p of the values at or below it.
double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const std::size_t rank = static_cast<std::size_t>(std::ceil(p * values.size()));
  return values[std::min(values.size(), std::max<std::size_t>(rank, 1)) - 1];
}

// OpenMesh's progressive mesh at run time, as ProgViewer's refine() and coarsen(): a split
// adds v0 and splits (TriMesh::vertex_split); a collapse finds the half-edge v0 -> v1 and
// collapses it, and a garbage collection after the collapses removes the deleted elements,
// so that the next split's new vertex takes v0's index again. Collapses need status flags.
class OpenMeshLod {
 public:
  explicit OpenMeshLod(const OpenMeshPm& pm) : pm_(pm) {
    mesh_.request_vertex_status();
    mesh_.request_edge_status();
    mesh_.request_face_status();
    load_base(pm, mesh_);
  }
  std::size_t level() const { return level_; }
  std::size_t face_count() const { return mesh_.n_faces(); }
  const OMesh& mesh() const { return mesh_; }
  void set_level(std::size_t level) {
    for (; level_ < level; ++level_) split(level_);
    if (level_ > level) {
      for (; level_ > level; --level_) collapse(level_ - 1);
      mesh_.garbage_collection();
    }
  }
  void set_face_count(std::size_t n) { set_level(pm_.level_for_faces(n)); }

 private:
  void split(std::size_t i) {
    const auto& r = pm_.records[i];
    mesh_.vertex_split(r.p0, OMesh::VertexHandle(r.v1), OMesh::VertexHandle(r.vl),
                       OMesh::VertexHandle(r.vr));
  }
  void collapse(std::size_t i) {
    const auto h = mesh_.find_halfedge(OMesh::VertexHandle(int(pm_.base_points.size() + i)),
                                       OMesh::VertexHandle(pm_.records[i].v1));
    if (!h.is_valid())
      die("OpenMesh: no half-edge v0 -> v1 to collapse for record " + std::to_string(i));
    mesh_.collapse(h);
  }
  const OpenMeshPm& pm_;
  OMesh mesh_;
  std::size_t level_ = 0;
};

// Bytes of a TriMesh, counted from its element counts: the connectivity (a half-edge per
// vertex, two half-edges of 4 handles each per edge, one per face) and every property
// (points; status flags when requested). Vector capacity beyond the size is not counted,
// so this is a lower bound.
std::size_t openmesh_bytes(const OMesh& mesh) {
  std::size_t bytes = mesh.n_vertices() * sizeof(OMesh::Vertex) +
                      mesh.n_edges() * sizeof(OMesh::Edge) + mesh.n_faces() * sizeof(OMesh::Face);
  auto add = [&](auto begin, auto end) {
    for (auto it = begin; it != end; ++it)
      if (*it) bytes += (*it)->size_of();
  };
  add(mesh.vprops_begin(), mesh.vprops_end());
  add(mesh.hprops_begin(), mesh.hprops_end());
  add(mesh.eprops_begin(), mesh.eprops_end());
  add(mesh.fprops_begin(), mesh.fprops_end());
  return bytes;
}

// ProgViewer's in-memory record (PMInfo: p0 and the handles v0, v1, vl, vr).
constexpr std::size_t kOpenMeshRecordBytes = sizeof(OMesh::Point) + 4 * sizeof(OMesh::VertexHandle);

// --- Latency ----------------------------------------------------------------------------

// Memory traffic between two changes: 64 MB read and written, 16 times the L2 cache, a stand-in
// for the rest of a frame. Without it the same change repeated finds its data in cache.
class Evictor {
 public:
  Evictor() : buffer_(64u << 20 >> 3, 1) {}
  void operator()() {
    uint64_t sum = 0;
    for (std::size_t i = 0; i < buffer_.size(); i += 8) sum += buffer_[i]++;
    sink_ = sum;
  }

 private:
  std::vector<uint64_t> buffer_;
  volatile uint64_t sink_ = 0;
};

// Microseconds per change. Refining and coarsening are kept apart as well: OpenMesh's
// coarsening ends in a garbage collection over the whole mesh, so its two directions differ
// by an order of magnitude and a median over both would fall between them.
struct Latency {
  std::vector<double> run_medians, refine_run_medians, coarsen_run_medians;
  std::vector<double> all;  // every change of every run
  double median() const { return pm::bench::median(run_medians); }
  double refine_median() const { return pm::bench::median(refine_run_medians); }
  double coarsen_median() const { return pm::bench::median(coarsen_run_medians); }
  double p99() const { return percentile(all, 0.99); }
};

// Changes of `delta` faces around `center`: up, back, down, back (only down and back at full
// detail), each timed alone. set(n) is set_face_count.
template <class SetFaces>
void time_changes(SetFaces&& set, std::size_t center, std::size_t delta, bool at_full, int changes,
                  Evictor* evict, Latency& latency) {
  const std::vector<std::size_t> cycle =
      at_full ? std::vector<std::size_t>{center - delta, center}
              : std::vector<std::size_t>{center + delta, center, center - delta, center};
  set(center);
  std::size_t at = center;
  std::vector<double> times, refine, coarsen;
  for (int k = 0; k < changes; ++k) {
    if (evict) (*evict)();
    const std::size_t target = cycle[k % cycle.size()];
    const auto start = Clock::now();
    set(target);
    const double microseconds = 1e6 * seconds_since(start);
    times.push_back(microseconds);
    (target > at ? refine : coarsen).push_back(microseconds);
    at = target;
  }
  latency.run_medians.push_back(median(times));
  latency.refine_run_medians.push_back(median(refine));
  latency.coarsen_run_medians.push_back(median(coarsen));
  latency.all.insert(latency.all.end(), times.begin(), times.end());
}

// --- The report -------------------------------------------------------------------------

std::string ms(double seconds) {
  return significant(1e3 * seconds);
}
std::string us(double microseconds) {
  return microseconds >= 1000 ? with_thousands(static_cast<std::size_t>(std::llround(microseconds)))
                              : significant(microseconds);
}
std::string rate(double per_second) {
  return with_thousands(static_cast<std::size_t>(std::llround(per_second)));
}
std::string times_ratio(double ratio) {
  return (ratio >= 1000 ? with_thousands(static_cast<std::size_t>(std::llround(ratio)))
                        : significant(ratio)) +
         "×";
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--mesh" && has_value)
      settings.mesh = argv[++i];
    else if (arg == "--steps" && has_value)
      settings.steps = std::atoi(argv[++i]);
    else if (arg == "--runs" && has_value)
      settings.runs = std::max(5, std::atoi(argv[++i]));
    else if (arg == "--cache" && has_value)
      settings.cache = argv[++i];
    else if (arg == "--out" && has_value)
      settings.out = argv[++i];
    else {
      std::fprintf(
          stderr,
          "usage: pm_bench_runtime [--mesh FILE] [--steps N] [--runs N (>= 5)] [--cache DIR] "
          "[--out FILE]\n"
          "  Times pm::RuntimeLod against OpenMesh's progressive-mesh replay on FILE (default\n"
          "  %s/stanford-bunny.obj) after N steps of Loop subdivision (default 2: x16).\n",
          pm::bench::shared_meshes_dir().c_str());
      return 2;
    }
  }
  if (settings.mesh.empty()) settings.mesh = pm::bench::shared_meshes_dir() + "/stanford-bunny.obj";
  if (settings.steps < 0 || settings.steps > 4) die("--steps must be 0 to 4");
  const int runs = settings.runs;
  const std::string load = pm::bench::command_output("cut -d' ' -f1-3 /proc/loadavg 2>/dev/null");

  // The input: a shared mesh made large by Loop subdivision (cached).
  pm::Mesh input;
  const auto subdivide_start = Clock::now();
  if (pm::Status s =
          pm::bench::load_subdivided(settings.mesh, settings.steps, settings.cache, input);
      !s)
    die(settings.mesh + ": " + s.message());
  const double input_seconds = seconds_since(subdivide_start);
  const std::string name =
      fs::path(settings.mesh).stem().string() + "-loop" + std::to_string(settings.steps);

  // Both progressive meshes, encoded once and cached.
  OurSetup our_setup;
  const pm::ProgressiveMesh pm = our_progressive_mesh(input, name, settings.cache, our_setup);
  OpenMeshSetup om_setup;
  const OpenMeshPm om_pm = openmesh_progressive_mesh(input, name, settings.cache, om_setup);
  const std::size_t input_faces = input.face_count();
  input = pm::Mesh();  // not needed any more: the measurements below get the memory

  // Ours: the runtime object's construction, then the replay's rates. RuntimeLod keeps what
  // every level needs (Hoppe 1998, §4-5), so it is built once, before the first frame.
  std::vector<double> construct_seconds;
  for (int r = 0; r < runs; ++r) {
    const auto start = Clock::now();
    pm::RuntimeLod lod(pm);
    construct_seconds.push_back(seconds_since(start));
  }
  std::fprintf(stderr, "ours: RuntimeLod built in %.0f ms (median)\n",
               1e3 * median(construct_seconds));
  pm::RuntimeLod lod(pm);
  const std::size_t our_splits = lod.max_level();

  // The replay, base to full and back, runs of ours and OpenMesh's interleaved.
  std::vector<double> our_refine, our_coarsen, om_refine, om_coarsen, om_collapse_loop, om_load;
  std::size_t om_bytes_lean = 0, om_bytes_status = 0, om_full_faces = 0, our_full_faces = 0;
  for (int r = 0; r < runs; ++r) {
    std::fprintf(stderr, "replay: run %d of %d\n", r + 1, runs);
    {
      // OpenMesh: a fresh TriMesh with nothing but points and connectivity for the splits
      // (the leanest it can be); status flags, which collapse() needs, added untimed after.
      OMesh mesh;
      auto start = Clock::now();
      load_base(om_pm, mesh);
      om_load.push_back(seconds_since(start));
      start = Clock::now();
      for (const auto& rec : om_pm.records)
        mesh.vertex_split(rec.p0, OMesh::VertexHandle(rec.v1), OMesh::VertexHandle(rec.vl),
                          OMesh::VertexHandle(rec.vr));
      om_refine.push_back(seconds_since(start));
      om_full_faces = mesh.n_faces();
      om_bytes_lean = openmesh_bytes(mesh);
      mesh.request_vertex_status();
      mesh.request_edge_status();
      mesh.request_face_status();
      om_bytes_status = openmesh_bytes(mesh);
      start = Clock::now();
      const int base = static_cast<int>(om_pm.base_points.size());
      for (std::size_t i = om_pm.records.size(); i-- > 0;) {
        const auto h = mesh.find_halfedge(OMesh::VertexHandle(base + int(i)),
                                          OMesh::VertexHandle(om_pm.records[i].v1));
        if (!h.is_valid())
          die("OpenMesh: no half-edge to collapse for record " + std::to_string(i));
        mesh.collapse(h);
      }
      om_collapse_loop.push_back(seconds_since(start));
      mesh.garbage_collection();
      om_coarsen.push_back(seconds_since(start));
      if (mesh.n_faces() != om_pm.base_faces.size() / 3)
        die("OpenMesh's coarsening missed the base mesh");
    }
    auto start = Clock::now();
    lod.set_level(lod.max_level());
    our_refine.push_back(seconds_since(start));
    our_full_faces = lod.face_count();
    start = Clock::now();
    lod.set_level(0);
    our_coarsen.push_back(seconds_since(start));
  }

  // extract_level at full detail, for reference: a fresh Mesh from the .pm, not in place.
  std::vector<double> extract_seconds;
  for (int r = 0; r < runs; ++r) {
    const auto start = Clock::now();
    const pm::Mesh full = pm::extract_level(pm, pm.split_count());
    extract_seconds.push_back(seconds_since(start));
    if (full.face_count() != input_faces) die("extract_level's full detail is not the input");
  }

  // Latency of a change of 1% of the full faces, at 10% and at 100% detail, ours and
  // OpenMesh's, with and without other memory traffic between changes.
  struct LatencyRow {
    const char* detail;
    bool at_full;
    bool evicted;
    Latency ours, openmesh;
    double our_levels = 0, om_levels = 0;  // splits per change
  };
  std::vector<LatencyRow> latency_rows;
  for (bool at_full : {false, true})
    for (bool evicted : {false, true})
      latency_rows.push_back({at_full ? "100%" : "10%", at_full, evicted, {}, {}});
  const std::size_t full_faces = our_full_faces;
  const std::size_t delta = full_faces / 100;
  const std::size_t om_delta = om_pm.full_faces() / 100;
  {
    Evictor evict;
    OpenMeshLod om_lod(om_pm);
    for (auto& row : latency_rows) {
      const std::size_t center = row.at_full ? full_faces : full_faces / 10;
      const std::size_t om_center = row.at_full ? om_pm.full_faces() : om_pm.full_faces() / 10;
      Evictor* e = row.evicted ? &evict : nullptr;
      for (int r = 0; r < runs; ++r) {
        std::fprintf(stderr, "latency at %s%s: run %d of %d\n", row.detail,
                     row.evicted ? ", evicted" : "", r + 1, runs);
        time_changes([&](std::size_t n) { lod.set_face_count(n); }, center, delta, row.at_full,
                     row.evicted ? 40 : 200, e, row.ours);
        time_changes([&](std::size_t n) { om_lod.set_face_count(n); }, om_center, om_delta,
                     row.at_full, row.evicted ? 8 : 20, e, row.openmesh);
      }
      lod.set_face_count(center);
      const std::size_t at = lod.level();
      lod.set_face_count(row.at_full ? center - delta : center + delta);
      row.our_levels = double(row.at_full ? at - lod.level() : lod.level() - at);
      const std::size_t om_at = om_pm.level_for_faces(om_center);
      const std::size_t om_to =
          om_pm.level_for_faces(row.at_full ? om_center - om_delta : om_center + om_delta);
      row.om_levels = double(row.at_full ? om_at - om_to : om_to - om_at);
    }
  }

  // Geomorphs (Hoppe 1996, §4.2): built once per transition, evaluated every frame.
  struct GeomorphRow {
    std::string name;
    std::size_t from = 0, to = 0, wedges = 0, morphing = 0;
    double construct = 0, evaluate = 0;
  };
  std::vector<GeomorphRow> geomorph_rows;
  const struct {
    const char* name;
    double from, to;
  } transitions[] = {
      {"10% → 11%", 0.10, 0.11}, {"50% → 100%", 0.50, 1.0}, {"0 (base) → 100%", 0.0, 1.0}};
  for (const auto& t : transitions) {
    GeomorphRow row;
    row.name = t.name;
    auto level_at = [&](double ratio) {
      if (ratio <= 0) return std::size_t{0};
      lod.set_face_count(static_cast<std::size_t>(std::llround(ratio * full_faces)));
      return lod.level();
    };
    row.from = level_at(t.from);
    row.to = level_at(t.to);
    std::vector<double> construct, evaluate;
    for (int r = 0; r < runs; ++r) {
      std::fprintf(stderr, "geomorph %s: run %d of %d\n", t.name, r + 1, runs);
      lod.set_level(row.from);
      auto start = Clock::now();
      const pm::RuntimeLod::Geomorph g = lod.geomorph(row.from, row.to);
      construct.push_back(seconds_since(start));
      row.wedges = g.wedge_count();
      // Buffers as a renderer keeps them, allocated once; the mesh has only positions, and
      // each kind it had would be blended alike.
      std::vector<float> positions(3 * g.wedge_count());
      std::vector<float> uvs(lod.uvs() ? 2 * g.wedge_count() : 0);
      std::vector<float> normals(lod.normals() ? 3 * g.wedge_count() : 0);
      std::vector<double> frames;
      constexpr int kFrames = 21;
      for (int k = 0; k < kFrames; ++k) {
        const float alpha = float(k) / (kFrames - 1);
        start = Clock::now();
        g.evaluate(alpha, positions.data(), uvs.empty() ? nullptr : uvs.data(),
                   normals.empty() ? nullptr : normals.data());
        frames.push_back(seconds_since(start));
      }
      evaluate.push_back(median(frames));
      // The wedges whose start differs from their end: those evaluate() blends.
      if (r == 0) {
        std::vector<float> start_positions(3 * g.wedge_count());
        g.evaluate(0, start_positions.data(), nullptr, nullptr);
        g.evaluate(1, positions.data(), nullptr, nullptr);
        row.morphing = 0;
        for (std::size_t w = 0; w < g.wedge_count(); ++w)
          row.morphing +=
              std::memcmp(&start_positions[3 * w], &positions[3 * w], 3 * sizeof(float)) != 0;
      }
    }
    row.construct = median(construct);
    row.evaluate = median(evaluate);
    geomorph_rows.push_back(row);
  }

  // --- The report ---
  const double our_refine_rate = our_splits / median(our_refine);
  const double our_coarsen_rate = our_splits / median(our_coarsen);
  const double om_refine_rate = om_pm.records.size() / median(om_refine);
  const double om_coarsen_rate = om_pm.records.size() / median(om_coarsen);
  const std::size_t our_bytes = lod.memory_bytes();
  lod.set_level(lod.max_level());
  const std::size_t our_vertices = lod.vertex_count();
  const std::size_t om_vertices = om_pm.full_vertices();

  std::ostringstream md;
  md << "# Runtime benchmark\n\n"
     << "Issue 6: `pm::RuntimeLod` (in-place refinement and coarsening, Hoppe 1998) against "
        "OpenMesh's progressive meshes on the ~1M-face mesh, in the same run. Regenerate with "
        "`bash tests/bench/run_runtime.sh`; how each number is measured is below the tables and "
        "in [README.md](README.md), \"Runtime\".\n\n"
     << pm::bench::run_description(PM_BENCH_SOURCE_DIR)
     << "- load average at the start (1, 5, 15 min): " << load
     << " (a shared machine: the "
        "neighbours' work is in every wall-clock time)\n"
     // OM_VERSION is 0xMMmmpp (0x90000 for 9.0); OpenMesh's own OM_GET_MAJ reads the wrong bits.
     << "- peer: OpenMesh " << (OM_VERSION >> 16) << "." << ((OM_VERSION >> 8) & 0xff) << "\n"
     << "- input: `" << fs::path(settings.mesh).filename().string() << "` after " << settings.steps
     << " steps of Loop subdivision (×" << (1 << (2 * settings.steps))
     << "): " << with_thousands(input_faces) << " faces, " << with_thousands(our_vertices)
     << " vertices\n"
     << "- every timing: the median of " << runs << " runs\n\n";

  md << "## Replay: base mesh to full detail and back\n\n"
     << "| | ours (`pm::RuntimeLod`) | OpenMesh (ProgViewer's replay) | ours / OpenMesh | target "
        "|\n"
     << "|---|---:|---:|---:|---|\n"
     << "| base mesh | " << with_thousands(pm.base_face_count()) << " faces | "
     << with_thousands(om_pm.base_faces.size() / 3) << " faces | | |\n"
     << "| vertex splits to full detail | " << with_thousands(our_splits) << " | "
     << with_thousands(om_pm.records.size()) << " | | |\n"
     << "| faces at full detail | " << with_thousands(our_full_faces) << " | "
     << with_thousands(om_full_faces) << " | | |\n"
     << "| base → full (ms) | " << ms(median(our_refine)) << " | " << ms(median(om_refine))
     << " | | |\n"
     << "| **vertex splits per second** | **" << rate(our_refine_rate) << "** | **"
     << rate(om_refine_rate) << "** | **" << times_ratio(our_refine_rate / om_refine_rate)
     << "** | ≥ 10×: " << (our_refine_rate >= 10 * om_refine_rate ? "holds" : "**does not hold**")
     << " |\n"
     << "| full → base (ms) | " << ms(median(our_coarsen)) << " | " << ms(median(om_coarsen))
     << " (collapses " << ms(median(om_collapse_loop)) << ", garbage collection "
     << ms(median(om_coarsen) - median(om_collapse_loop)) << ") | | |\n"
     << "| edge collapses per second | " << rate(our_coarsen_rate) << " | " << rate(om_coarsen_rate)
     << " | " << times_ratio(our_coarsen_rate / om_coarsen_rate) << " | |\n\n";

  md << "## Latency of a change of 1% of the faces\n\n"
     << "Ours: " << with_thousands(delta) << " faces (1% of " << with_thousands(full_faces)
     << "); OpenMesh: " << with_thousands(om_delta) << ". Microseconds per change: the median (of "
     << "the runs' medians) and the 99th percentile of all changes of all runs, refining and "
        "coarsening together; OpenMesh's median also for each direction apart, since its "
        "coarsening ends in a garbage collection of the whole mesh. The ratio takes OpenMesh's "
        "faster direction.\n\n"
     << "| detail | between changes | splits per change (ours / OpenMesh) | ours median | ours p99 "
        "| "
        "OpenMesh median: refine / coarsen | OpenMesh p99 | OpenMesh refine / ours | target: under "
        "1 ms |\n"
     << "|---|---|---:|---:|---:|---:|---:|---:|---|\n";
  for (const auto& row : latency_rows) {
    const bool holds = row.ours.p99() < 1000;
    md << "| " << row.detail << " | "
       << (row.evicted ? "64 MB of other memory traffic" : "nothing (warm caches)") << " | "
       << with_thousands(std::size_t(row.our_levels)) << " / "
       << with_thousands(std::size_t(row.om_levels)) << " | " << us(row.ours.median()) << " | "
       << us(row.ours.p99()) << " | " << us(row.openmesh.refine_median()) << " / "
       << us(row.openmesh.coarsen_median()) << " | " << us(row.openmesh.p99()) << " | "
       << times_ratio(row.openmesh.refine_median() / row.ours.median()) << " | "
       << (holds ? "holds (p99)" : "**does not hold** (p99)") << " |\n";
  }
  md << "\n";

  md << "## Memory\n\n"
     << "| | bytes | per vertex | per face |\n|---|---:|---:|---:|\n"
     << "| **`pm::RuntimeLod::memory_bytes()`** (every level) | " << with_thousands(our_bytes)
     << " | **" << significant(double(our_bytes) / our_vertices) << "** | "
     << significant(double(our_bytes) / our_full_faces) << " |\n";
  const std::size_t om_records_bytes = om_pm.records.size() * kOpenMeshRecordBytes;
  const struct {
    const char* what;
    std::size_t bytes;
  } om_memory[] = {
      {"OpenMesh TriMesh at full detail: points and connectivity", om_bytes_lean},
      {"the same with status flags (collapse() needs them)", om_bytes_status},
      {"the same plus ProgViewer's records in memory (what coarsening and refining need)",
       om_bytes_status + om_records_bytes},
  };
  for (const auto& m : om_memory)
    md << "| " << m.what << " | " << with_thousands(m.bytes) << " | "
       << significant(double(m.bytes) / om_vertices) << " | "
       << significant(double(m.bytes) / om_full_faces) << " |\n";
  md << "\n";

  md << "## Geomorphs\n\n"
     << "`RuntimeLod::geomorph(from, to)` once per transition, then `Geomorph::evaluate(alpha, "
        "...)` "
        "every frame (positions; this mesh has no other attribute). Milliseconds.\n\n"
     << "| transition | levels | wedges | morphing wedges | geomorph() (refines to `to`) | "
        "evaluate() per frame | "
        "ns per wedge |\n|---|---|---:|---:|---:|---:|---:|\n";
  for (const auto& row : geomorph_rows)
    md << "| " << row.name << " | " << with_thousands(row.from) << " → " << with_thousands(row.to)
       << " | " << with_thousands(row.wedges) << " | " << with_thousands(row.morphing) << " | "
       << ms(row.construct) << " | **" << ms(row.evaluate) << "** | "
       << significant(1e9 * row.evaluate / row.wedges) << " |\n";
  md << "\n";

  md << "## One-time costs, for reference\n\n| step | ms |\n|---|---:|\n"
     << "| `pm::RuntimeLod` construction from the `.pm` (median) | "
     << ms(median(construct_seconds)) << " |\n"
     << "| `pm::extract_level(pm, full)`: a fresh `Mesh` of full detail (median) | "
     << ms(median(extract_seconds)) << " |\n"
     << "| OpenMesh: base mesh into a TriMesh (median) | " << ms(median(om_load)) << " |\n"
     << "| `pm::encode`, default options | "
     << (our_setup.encode_seconds < 0 ? "cached" : ms(our_setup.encode_seconds)) << " |\n"
     << "| OpenMesh: `DecimaterT` to the end with ModProgMeshT | "
     << (om_setup.decimate_seconds < 0 ? "cached" : ms(om_setup.decimate_seconds)) << " |\n"
     << "| input: read (and subdivide, unless cached) | " << ms(input_seconds) << " |\n\n";

  md << "## How it is measured\n\n"
     << "- **Encoding.** Ours: `pm::encode` with `EncodeOptions{}` (pmenc's defaults). OpenMesh: "
        "`DecimaterT<TriMesh_ArrayKernelT<>>` with `ModQuadricT` (`unset_max_err()`, the "
        "priority), "
        "`ModNormalFlippingT` at 90° and `ModProgMeshT`, `decimate(0)` (until no collapse is "
        "legal), "
        "then `ModProgMeshT::write()`. Both files are cached in the build directory.\n"
     << "- **Replay.** Ours: `set_level(max_level())` from level 0, then `set_level(0)`. OpenMesh, "
        "as its ProgViewer: the base mesh into a fresh TriMesh (untimed; reserved for the full "
        "mesh, which ProgViewer does not do), then per record `vertex_split(p0, v1, vl, vr)`, "
        "timed alone; then (status flags requested, untimed) per record from the last "
        "`find_halfedge(v0, v1)` and `collapse()`, and `garbage_collection()`, timed together as "
        "ProgViewer's coarsen(). Rates: each side's own number of splits over its median time.\n"
     << "- **Latency.** `set_face_count(n)` around n = 10% and 100% of the full faces, by 1% of "
        "them: up, back, down, back (at 100%: down, back), each change timed alone; 200 changes "
        "per run for ours, 20 for OpenMesh (40 and 8 with the memory traffic). OpenMesh's side is "
        "the same walk over its own records (a TriMesh with status flags: splits; collapses and a "
        "garbage collection, which moves faces and edges into the holes but keeps every vertex's "
        "index, the deleted vertices being the last, so the next split gets v0's index back). \"64 "
        "MB of other memory traffic\": a 64 MB buffer read and "
        "written between changes (untimed), so the change does not find its data in the caches "
        "the previous change warmed.\n"
     << "- **Memory.** Ours: `RuntimeLod::memory_bytes()` (capacities of all its arrays), per "
        "vertex and face of full detail. OpenMesh: counted from the element counts, "
        "`sizeof(Vertex)`, `sizeof(Edge)` (two half-edges with prev) and `sizeof(Face)` times "
        "their numbers plus every property's `size_of()` (points, and status flags when "
        "requested); capacity slack not counted. Records: ProgViewer's PMInfo (a point and four "
        "handles, "
     << kOpenMeshRecordBytes << " bytes).\n"
     << "- **Geomorphs.** Levels by face count (`set_face_count`), `geomorph(from, to)` timed "
        "once per run; `evaluate(alpha)` for 21 values of alpha in [0, 1] into buffers allocated "
        "before, the median per run, then the median of the runs. Morphing wedges: those whose "
        "position at alpha 0 and 1 differ.\n";

  const std::string text = md.str();
  std::fputs(text.c_str(), stdout);
  if (!settings.out.empty()) {
    std::ofstream out(settings.out, std::ios::binary);
    out << text;
    if (!out) die("cannot write " + settings.out);
  }
  return 0;
}
