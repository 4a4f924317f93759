// pm_bench_encode: the in-process time of pm::encode on one mesh (issue 10), for iterating
// on the encoder's speed: user CPU and wall seconds of encode() alone (not reading nor
// writing), and an FNV-1a hash of the written .pm, so that two builds' outputs can be
// compared without keeping the files.
//
//   pm_bench_encode MESH [--metric quadric|schroeder] [--fast] [--one-heap] [--sequence]
//                   [--partition VERTICES] [--threads N] [--runs N] [--out FILE.pm] [--write]
//                   [--zstd-level N]
//
// --write: also the time of pm::write_pm() on the encoded mesh (the .pm's bytes from the
// progressive mesh: the splits' codes and zstd; default WriteOptions, EncodeOptions::threads
// threads), each run writing again; printed on a second line. --zstd-level: WriteOptions's
// (pmenc --zstd-level), for the written bytes whether timed or not.
// --sequence: the collapse sequence alone (issue 25's speed line: as pm::encode runs it,
// attributes kept unless the mesh has none; a mesh that needs a repair repaired before the
// timer starts, sequence_timing.h), instead of the whole encode();
// it prints the collapses as splits, and writes nothing (bytes 0, hash of nothing).
// --one-heap: the collapse loop without regions (EncodeOptions::fast_partition_vertices = 0);
// --partition: regions from that many vertices (fast_partition_vertices) instead of the default;
// --threads: EncodeOptions::threads. --fast: EncodeOptions::fast, the collapse loop without its
// measured distance (pmenc --fast). The mesh's own size never chooses --fast here
// (EncodeOptions::fast_from stays 0), so --fast alone says which loop ran.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "pm/encoder.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "sequence_timing.h"

namespace {

double user_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_utime.tv_sec) + 1e-6 * double(usage.ru_utime.tv_usec);
}

// User CPU and wall seconds of each run of something, and their middle values (the upper of
// the two for an even count), as this program has always printed them.
struct Timings {
  std::vector<double> user, wall;
  template <typename Run>
  void time(Run&& run) {
    const double user0 = user_seconds();
    const auto wall0 = std::chrono::steady_clock::now();
    run();
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count());
    user.push_back(user_seconds() - user0);
  }
  static double middle(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    return values[values.size() / 2];
  }
  double user_middle() const { return middle(user); }
  double wall_middle() const { return middle(wall); }
};

[[noreturn]] void die(const std::string& message) {
  std::fprintf(stderr, "pm_bench_encode: %s\n", message.c_str());
  std::exit(1);
}

}  // namespace

int main(int argc, char** argv) {
  std::string path, out;
  pm::EncodeOptions options;
  int runs = 1;
  bool sequence_only = false, time_write = false;
  int zstd_level = pm::WriteOptions{}.zstd_level;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--metric" && i + 1 < argc) {
      const std::string m = argv[++i];
      if (m == "quadric") options.metric = pm::Metric::kQuadric;
      else if (m == "schroeder") options.metric = pm::Metric::kSchroeder;
      else die("unknown metric " + m);
    } else if (arg == "--fast") {
      options.fast = true;  // the collapse loop without its measured distance (pmenc --fast)
    } else if (arg == "--sequence") {
      sequence_only = true;
    } else if (arg == "--one-heap") {
      options.fast_partition_vertices = 0;
    } else if (arg == "--partition" && i + 1 < argc) {
      options.fast_partition_vertices = std::strtoull(argv[++i], nullptr, 10);
    } else if (arg == "--threads" && i + 1 < argc) {
      options.threads = static_cast<unsigned>(std::max(0, std::atoi(argv[++i])));
    } else if (arg == "--layer-window" && i + 1 < argc) {
      options.layer_window = std::atof(argv[++i]);
    } else if (arg == "--runs" && i + 1 < argc) {
      runs = std::max(1, std::atoi(argv[++i]));
    } else if (arg == "--write") {
      time_write = true;
    } else if (arg == "--zstd-level" && i + 1 < argc) {
      zstd_level = std::atoi(argv[++i]);
    } else if (arg == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (path.empty()) {
      path = arg;
    } else {
      die("usage: pm_bench_encode MESH [--metric quadric|schroeder] [--fast] [--one-heap] "
          "[--sequence] [--partition VERTICES] [--threads N] [--layer-window SHARE] [--runs N] "
          "[--out FILE] [--write] [--zstd-level N]");
    }
  }
  if (path.empty()) die("usage: pm_bench_encode MESH [--metric quadric|schroeder] [--runs N]");
  if (time_write && sequence_only) die("--write times write_pm of the whole encode: not with --sequence");
  pm::Mesh mesh;
  if (pm::Status s = pm::read_mesh(path, mesh); !s) die("reading " + path + ": " + s.message());
  Timings encoding, writing;
  std::string bytes;
  pm::ProgressiveMesh progressive;
  std::size_t splits = 0;
  std::optional<pm::bench::CollapseSequenceRun> sequence_run;
  if (sequence_only) sequence_run.emplace(mesh, options);
  for (int r = 0; r < runs; ++r) {
    pm::Simplification sequence;
    // A mesh that needs a repair is repaired before the timer starts (sequence_timing.h).
    if (sequence_run)
      if (pm::Status s = sequence_run->prepare(); !s) die("repair: " + s.message());
    encoding.time([&] {
      if (sequence_run) {
        if (pm::Status s = sequence_run->run(sequence); !s)
          die("the collapse sequence: " + s.message());
      } else if (pm::Status s = pm::encode(mesh, options, progressive); !s) {
        die("encode: " + s.message());
      }
    });
    splits = sequence_only ? sequence.collapses.size() : progressive.splits.size();
  }
  if (!sequence_only) {
    pm::WriteOptions write;
    write.threads = options.threads;
    write.zstd_level = zstd_level;
    for (int r = 0; r < (time_write ? runs : 1); ++r) {
      writing.time([&] {
        if (pm::Status s = pm::write_pm(progressive, write, bytes); !s) die("write: " + s.message());
      });
    }
  }
  uint64_t hash = 1469598103934665603ull;
  for (unsigned char c : bytes) hash = (hash ^ c) * 1099511628211ull;
  if (!out.empty()) std::ofstream(out, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  std::printf("%s faces %zu splits %zu user %.3f wall %.3f (median of %d) bytes %zu hash %016llx\n",
              path.c_str(), mesh.face_count(), splits, encoding.user_middle(),
              encoding.wall_middle(), runs, bytes.size(), static_cast<unsigned long long>(hash));
  if (time_write) {
    std::printf("%s write_pm user %.3f wall %.3f (median of %d)\n", path.c_str(),
                writing.user_middle(), writing.wall_middle(), static_cast<int>(writing.wall.size()));
  }
  return 0;
}
