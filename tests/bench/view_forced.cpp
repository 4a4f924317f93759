// pm_bench_forced: how much refinement the dependencies of selective refinement force (issue 7).
// For each shared mesh (encoded with the default options), random spheres around random
// vertices: the splits a region wants (those whose bounding sphere meets it, found top-down
// through the hierarchy as SelectiveRefinement::refine_sphere does) against the splits applied
// once the set is closed under the dependencies (SelectiveRefinement::set_applied), under
// Hoppe 1997's rule (the default) and under DependencyRule::kExactRing (the rule before it).
// The ratio is the forced refinement: 1 would be none. Markdown on stdout (and --out FILE).
//
//   pm_bench_forced [--meshes DIR] [--regions N] [--radius R] [--out FILE]
//
// R is the spheres' radius as a fraction of the mesh's box diagonal (default 0.02).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench_report.h"
#include "pm/encoder.h"
#include "pm/mesh_io.h"
#include "pm/selective_refinement.h"

namespace {

[[noreturn]] void die(const std::string& message) {
  std::fprintf(stderr, "pm_bench_forced: %s\n", message.c_str());
  std::exit(1);
}

}  // namespace

int main(int argc, char** argv) {
  std::string meshes = std::string(PM_BENCH_SOURCE_DIR) + "/../shared/meshes", out;
  int regions = 20;
  double radius_fraction = 0.02;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--meshes" && has_value)
      meshes = argv[++i];
    else if (arg == "--regions" && has_value)
      regions = std::atoi(argv[++i]);
    else if (arg == "--radius" && has_value)
      radius_fraction = std::atof(argv[++i]);
    else if (arg == "--out" && has_value)
      out = argv[++i];
    else
      die("usage: pm_bench_forced [--meshes DIR] [--regions N] [--radius R] [--out FILE]");
  }
  const char* names[] = {"stanford-bunny.obj", "fandisk.obj", "spot.obj",  "armadillo.off",
                         "nefertiti.obj",      "rocker-arm.obj", "cow.obj", "homer.obj"};
  std::ostringstream md;
  md << "# Forced refinement of selective refinement (issue 7)\n\n"
     << pm::bench::run_description(PM_BENCH_SOURCE_DIR) << "\n"
     << regions << " spheres per mesh, each around a random vertex (seed 7), radius "
     << pm::bench::significant(radius_fraction) << " of the box diagonal. Wanted: the splits "
     << "whose bounding sphere meets the region (top-down through the hierarchy). Applied: "
     << "the wanted splits closed under the dependencies, by Hoppe 1997's rule (the parent and "
     << "the creators of fn0..fn3, the default) and by `kExactRing` (the last modifier of every "
     << "face around the split's vertex, the rule before). Sums over the spheres; the worst "
     << "sphere is the one with the largest applied / wanted under Hoppe 1997's rule.\n\n"
     << "| mesh | splits | wanted | applied (Hoppe 1997) | per wanted | applied (exact ring) "
     << "| per wanted | worst sphere: wanted -> Hoppe 1997, exact ring |\n"
     << "|---|---:|---:|---:|---:|---:|---:|---|\n";
  std::size_t all_wanted = 0, all_applied = 0, all_exact = 0;
  for (const char* name : names) {
    const std::string path = meshes + "/" + name;
    pm::Mesh input;
    if (!pm::read_mesh(path, input).ok()) {
      std::fprintf(stderr, "skipping %s (cannot read it)\n", path.c_str());
      continue;
    }
    pm::ProgressiveMesh pm;
    if (pm::Status s = pm::encode(input, pm::EncodeOptions{}, pm); !s) die(path + ": " + s.message());
    pm::SelectiveRefinement r(pm), exact(pm, pm::DependencyRule::kExactRing);
    const std::size_t n = r.split_count();
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (std::size_t i = 0; i < pm.positions.size(); ++i) {
      lo[i % 3] = std::min(lo[i % 3], double(pm.positions[i]));
      hi[i % 3] = std::max(hi[i % 3], double(pm.positions[i]));
    }
    const double diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                                      (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                      (hi[2] - lo[2]) * (hi[2] - lo[2]));
    const double radius = radius_fraction * diagonal;
    std::mt19937 random(7);
    std::uniform_int_distribution<uint32_t> pick(0, static_cast<uint32_t>(pm.vertex_count() - 1));
    std::size_t wanted_sum = 0, applied_sum = 0, exact_sum = 0, worst_wanted = 0, worst_applied = 0,
                worst_exact = 0;
    double worst_ratio = 0;
    for (int k = 0; k < regions; ++k) {
      const uint32_t centre_vertex = pick(random);
      const double c[3] = {pm.positions[3 * std::size_t{centre_vertex}],
                           pm.positions[3 * std::size_t{centre_vertex} + 1],
                           pm.positions[3 * std::size_t{centre_vertex} + 2]};
      std::vector<bool> wanted(n, false);
      std::vector<uint32_t> stack;
      for (uint32_t j = 0; j < n; ++j)
        if (r.parent(j) == pm::kNoSplit) stack.push_back(j);
      std::size_t count = 0;
      while (!stack.empty()) {
        const uint32_t j = stack.back();
        stack.pop_back();
        const pm::SplitBounds& b = r.bounds(j);
        const double d = std::sqrt((b.center[0] - c[0]) * (b.center[0] - c[0]) +
                                   (b.center[1] - c[1]) * (b.center[1] - c[1]) +
                                   (b.center[2] - c[2]) * (b.center[2] - c[2]));
        if (d > radius + b.radius) continue;
        wanted[j] = true;
        ++count;
        for (uint32_t child : {r.child_u(j), r.child_v(j)})
          if (child != pm::kNoSplit) stack.push_back(child);
      }
      r.set_applied(wanted);
      exact.set_applied(wanted);
      const std::size_t applied = r.applied_count(), applied_exact = exact.applied_count();
      wanted_sum += count;
      applied_sum += applied;
      exact_sum += applied_exact;
      const double ratio = count ? double(applied) / count : 1;
      if (ratio > worst_ratio)
        worst_ratio = ratio, worst_wanted = count, worst_applied = applied, worst_exact = applied_exact;
    }
    all_wanted += wanted_sum;
    all_applied += applied_sum;
    all_exact += exact_sum;
    const double per = 1.0 / std::max<std::size_t>(wanted_sum, 1);
    md << "| " << name << " | " << pm::bench::with_thousands(n) << " | "
       << pm::bench::with_thousands(wanted_sum) << " | " << pm::bench::with_thousands(applied_sum)
       << " | " << pm::bench::significant(applied_sum * per) << " | "
       << pm::bench::with_thousands(exact_sum) << " | " << pm::bench::significant(exact_sum * per)
       << " | " << pm::bench::with_thousands(worst_wanted) << " -> "
       << pm::bench::with_thousands(worst_applied) << ", " << pm::bench::with_thousands(worst_exact)
       << " |\n";
    std::fprintf(stderr, "%s: %zu wanted, %zu applied, %zu under the exact ring\n", name,
                 wanted_sum, applied_sum, exact_sum);
  }
  const double per = 1.0 / std::max<std::size_t>(all_wanted, 1);
  md << "| all | | " << pm::bench::with_thousands(all_wanted) << " | "
     << pm::bench::with_thousands(all_applied) << " | " << pm::bench::significant(all_applied * per)
     << " | " << pm::bench::with_thousands(all_exact) << " | "
     << pm::bench::significant(all_exact * per) << " | |\n";
  const std::string report = md.str();
  std::fputs(report.c_str(), stdout);
  if (!out.empty()) {
    std::ofstream file(out);
    file << report;
    if (!file) die("cannot write " + out);
  }
  return 0;
}
