// pm_bench_decode_stream: the native side of the web decode benchmark (web/bench/run_decode.sh,
// issue 28). It times what the WebAssembly decoder's full decode does, from the stream's bytes
// in memory to the full-detail mesh: pm::read_pm, then pm::extract_level at the last split.
// Neither reading the file nor writing a mesh is in the time, nor the process's start.
//
//   pm_bench_decode_stream STREAM.pm
//
// Prints one line: read_ms=R full_ms=F cpu_ms=C faces=N: wall-clock milliseconds of read_pm
// and of the whole decode (F includes R), and the process's CPU time in the whole decode (the
// reader is single-threaded: on a loaded machine, the time it was given the CPU). Exit code 1
// when the stream does not decode, 2 for a bad command line. The script runs it once per run,
// alternating with node, so that a change in the machine's load hits both decoders alike.
#include <time.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "big_mesh.h"
#include "pm/lod.h"
#include "pm/pm_codec.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: pm_bench_decode_stream STREAM.pm\n");
    return 2;
  }
  std::string bytes;
  if (!pm::bench::read_file(argv[1], bytes)) {
    std::fprintf(stderr, "pm_bench_decode_stream: %s: cannot read it\n", argv[1]);
    return 1;
  }
  using Clock = std::chrono::steady_clock;
  const auto cpu_ms = [] {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
  };
  const double cpu_start = cpu_ms();
  const auto start = Clock::now();
  pm::ProgressiveMesh progressive;
  if (pm::Status s = pm::read_pm(bytes, progressive); !s) {
    std::fprintf(stderr, "pm_bench_decode_stream: %s: %s\n", argv[1], s.message().c_str());
    return 1;
  }
  const auto read = Clock::now();
  const pm::Mesh full = pm::extract_level(progressive, progressive.split_count());
  const auto end = Clock::now();
  const double cpu = cpu_ms() - cpu_start;
  const auto ms = [](Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
  std::printf("read_ms=%.3f full_ms=%.3f cpu_ms=%.3f faces=%zu\n", ms(read - start), ms(end - start),
              cpu, full.face_count());
  return 0;
}
