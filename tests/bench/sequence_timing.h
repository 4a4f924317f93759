// The collapse sequence alone, timed: issue 25's speed line (pm_bench_fast, pm_bench_encode
// --sequence). pm::encode runs the loop on the input as it is when it is a manifold that needs
// no repair (simplify_direct), and otherwise on pmenc's repair of it (build_manifold_mesh,
// then simplify). The repair is no part of the collapse sequence, so it is made before the
// timer starts; the loop then runs on it as encode() runs it. Without this, a mesh that needs
// a repair (the bunny, 69,451 faces, one of the speed line's meshes; the cow) had no time.
// Internal to the benchmarks: it reaches into lib/src/simplify.
#pragma once

#include <string>

#include "pm/encoder.h"
#include "pm/mesh.h"
#include "simplify/simplifier.h"

namespace pm::bench {

class CollapseSequenceRun {
 public:
  // Decides, once per mesh, whether the loop needs the repair: simplify_direct refuses such a
  // mesh before its loop runs. The refusal's time is no part of any timing.
  CollapseSequenceRun(const pm::Mesh& mesh, const pm::EncodeOptions& options)
      : mesh_(mesh), options_(options) {
    pm::Simplification probe;
    repaired_ = !pm::simplify_direct(mesh_, options_, probe);
  }
  bool repaired() const { return repaired_; }

  // Before each timed run(): the repair, when the mesh needs it (simplify() consumes it).
  pm::Status prepare() {
    if (!repaired_) return pm::Status::ok();
    manifold_ = pm::ManifoldMesh{};
    return pm::build_manifold_mesh(mesh_, manifold_);
  }
  // The collapse sequence, as pm::encode runs it: time this call alone.
  pm::Status run(pm::Simplification& out) {
    if (repaired_) return pm::simplify(mesh_, manifold_, options_, out);
    if (!pm::simplify_direct(mesh_, options_, out))
      return pm::Status(pm::ErrorCode::kInternal, "simplify_direct refused a mesh it took before");
    return pm::Status::ok();
  }

 private:
  const pm::Mesh& mesh_;
  pm::EncodeOptions options_;
  bool repaired_ = false;
  pm::ManifoldMesh manifold_;
};

}  // namespace pm::bench
