// pm_bench_python_peer: the C++ side of python/bench/bench.py. The same calls pmesh makes,
// timed the same way: pm::encode of a mesh read beforehand, and a level per ratio as
// ProgressiveMesh.level(ratio=R) makes it: pm::level_for_faces of the ratio's face count,
// then pm::extract_level. A level's time is the median of SAMPLES samples, each the mean of
// CALLS calls timed together (a call of half a millisecond is then not measured alone, at the
// clock's and the scheduler's mercy). One line per measurement on stdout: "encode SECONDS",
// then "level RATIO SECONDS FACES" per ratio.
//
//   pm_bench_python_peer MESH SAMPLES CALLS RATIO...
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/mesh_io.h"

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: pm_bench_python_peer MESH SAMPLES CALLS RATIO...\n");
    return 2;
  }
  const int samples = std::max(1, std::atoi(argv[2]));
  const int calls = std::max(1, std::atoi(argv[3]));
  pm::Mesh mesh;
  if (pm::Status s = pm::read_mesh(argv[1], mesh); !s) {
    std::fprintf(stderr, "pm_bench_python_peer: %s: %s\n", argv[1], s.message().c_str());
    return 1;
  }
  pm::ProgressiveMesh progressive;
  const auto start = std::chrono::steady_clock::now();
  if (pm::Status s = pm::encode(mesh, pm::EncodeOptions{}, progressive); !s) {
    std::fprintf(stderr, "pm_bench_python_peer: encode: %s\n", s.message().c_str());
    return 1;
  }
  std::printf("encode %.6f\n", seconds_since(start));
  const std::size_t full = pm::faces_at_level(progressive, progressive.splits.size());
  for (int r = 4; r < argc; ++r) {
    const double ratio = std::atof(argv[r]);
    const std::size_t wanted = std::size_t(std::llround(ratio * double(full)));
    std::vector<double> times;
    std::size_t faces = 0;
    for (int i = 0; i < samples; ++i) {
      const auto sample_start = std::chrono::steady_clock::now();
      for (int c = 0; c < calls; ++c) {
        const pm::Mesh lod = pm::extract_level(progressive, pm::level_for_faces(progressive, wanted));
        faces = lod.face_count();
      }
      times.push_back(seconds_since(sample_start) / calls);
    }
    std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
    std::printf("level %s %.7f %zu\n", argv[r], times[times.size() / 2], faces);
  }
  return 0;
}
