// Building a progressive mesh from an input mesh: repair to a manifold half-edge mesh,
// then a priority-ordered sequence of half-edge collapses (Schroeder 1992, 1997).
#pragma once

#include <cstddef>
#include <functional>

#include "pm/mesh.h"
#include "pm/pm_codec.h"
#include "pm/progressive_mesh.h"
#include "pm/status.h"

namespace pm {

// How the cost of a collapse is measured.
enum class Metric {
  kSchroeder,  // Schroeder 1992/1997: distance to the average plane or feature line, accumulated
  kQuadric,    // Garland and Heckbert 1997: quadric error, accumulated by summing quadrics
};

// pmenc's and pmesh's default EncodeOptions::fast_from: a million faces, where the measured
// loop takes 25 s of CPU and more (tests/bench/scale.md).
inline constexpr std::size_t kDefaultFastFrom = 1000000;

struct EncodeOptions {
  // Quadric by default: its levels measure closer to the input than Schroeder's on every
  // mesh and target of tests/bench/quality.md.
  Metric metric = Metric::kQuadric;
  // Edges whose two faces' normals differ by more than this are feature edges
  // (Schroeder 1992, §3 "feature angle"). Negative: the metric's default_feature_angle().
  double feature_angle_deg = -1;
  // A collapse may not turn any face normal by more than this.
  double max_normal_flip_deg = 90.0;
  // Never remove corner vertices (the report's behaviour; may stall early).
  bool keep_corners = false;
  // Geometry only: colours, texture coordinates, normals and materials are not encoded
  // (pmenc --drop-attributes). By default every attribute of the input is kept.
  bool drop_attributes = false;
  // Record the input's vertex and face order, so that full detail lists them in that order
  // (pmenc --keep-order; ProgressiveMesh::input_vertices, input_faces). It costs about
  // log2(n) bits per vertex and per face in the .pm.
  bool keep_order = false;
  // Reorder the splits into layers of independent splits, which the .pm stream codes more
  // compactly: u as a small gap from the previous u of its layer instead of a global vertex
  // id (layer_splits in pm/advanced/stream_order.h; Pajarola and Rossignac 2000, §3). Each
  // window of at most this share of the vertices before it is reordered on its own, inside
  // the stream's chunks: those of the WriteOptions given to encode() (the same object the
  // caller then gives write_pm, so the two cannot disagree), WriteOptions{}'s without. The
  // levels at window ends are the simplifier's; a level inside a window has as many
  // vertices as the greedy level it replaces, and an error bound no larger than the
  // window's first level's.
  // The default, 1/16: the lossless .pm 2 to 10% smaller and the 14-bit one 4 to 21% on
  // the shared meshes (25% lossless on a 1.6M-face mesh), the levels' RMS distance to the
  // input within 2% of the greedy order's (tests/bench/size.md). 0: keep the simplifier's
  // order. Infinity: whole chunks (smaller still, but a level inside a chunk may be much
  // coarser: fandisk at 259 faces, Hausdorff 0.36% -> 0.60% of the diagonal).
  // pmenc --layer-window, --layered.
  double layer_window = 1.0 / 16;
  // The one collapse loop (issue 25) runs either metric on a flat connectivity, with
  // texture coordinates, normals, colours and materials kept with their seams. By default
  // its key adds a measured distance: a few removed input vertices kept per face, and the
  // faces that change measured against the input (tests/bench/fast.md, quality.md).
  // fast: the same loop without that measure, its key the metric's cost alone (on the
  // geometry alone, the quadric's with a plane term): 3.7 times faster on nefertiti (100K
  // faces), 3.2 times on a 1.6M-face mesh (tests/bench/scale.md), levels a little closer to
  // the input than meshoptimizer's (tests/bench/fast_unmeasured.md), the Hausdorff distance
  // 1.6 times the measured loop's and the RMS 1.2 times. Either way the recorded errors bound
  // every input vertex's distance to the level (tests/bench/bound.md). pmenc --fast.
  bool fast = false;
  // Meshes of at least this many input faces take `fast` whatever it says: the measure costs
  // 3.2 times the time on 1.6 million faces, 16.4 s against 5.1 s (tests/bench/scale.md). 0:
  // only `fast` decides. The library's default leaves the choice to the caller; pmenc --fast-from
  // and pmesh's fast_from default to kDefaultFastFrom. EncodeStats::fast says which loop ran.
  std::size_t fast_from = 0;
  // The collapse loop on a mesh of at least this many vertices, without welds or faces carried
  // by the repair: its collapses run in rounds, each in eight regions of the mesh at once
  // (on `threads` threads; with the measured distance, down to two near the end), then merged in
  // order of cost; the last thirty-second run in one heap. The sequence is the same whatever
  // the number of threads, but not exactly the one-heap greedy order (vertices next to a
  // region's edge wait for a later round). 0 or SIZE_MAX: never. From 16,384: with the
  // measured distance a collapse costs enough for the regions to pay from there (two threads,
  // medians of 5: nefertiti 1.26 -> 0.88 s, the bunny 0.67 -> 0.53, armadillo 0.52 -> 0.43;
  // one thread about the same, -5% to +5%; the levels as close to the input, Hausdorff 0.999
  // and RMS 1.000 times one heap's, geometric means over their 50/10/2% levels).
  std::size_t fast_partition_vertices = 16384;
  // Threads the collapse loop may use (its regions, and parts of building its arrays), and the
  // splits' layers (two stages at once): 0, the machine's cores. The result is the same for
  // any number.
  unsigned threads = 0;
  // Stop when the mesh would go below either count (0: no limit).
  std::size_t min_faces = 0;
  std::size_t min_vertices = 0;
  // Called now and then with the fraction of work done, in [0, 1]. May be empty.
  std::function<void(double)> progress;
};

// 30 degrees for schroeder, whose error needs feature lines (Schroeder 1992, §3). 180 for
// quadric: no edge is a feature by its angle, only boundaries are held. The quadrics'
// planes keep creases on their own, and angle features would forbid the collapses that
// keep the measured error lowest (tests/bench/quality.md).
double default_feature_angle(Metric metric);
// options.feature_angle_deg, or the metric's default when it is negative.
double effective_feature_angle(const EncodeOptions& options);

// What the encoder changed to make the input a manifold half-edge mesh. Nothing is lost:
// each repair is undone at full detail.
struct RepairReport {
  std::size_t vertices_duplicated = 0;  // copies made at pinched vertices and complex edges
  std::size_t complex_edges = 0;        // edges with more than two faces or inconsistent ones
  std::size_t carried_faces = 0;        // faces with a repeated vertex, carried as-is
  std::size_t loose_vertices = 0;       // vertices no face uses
  bool any() const {
    return vertices_duplicated || complex_edges || carried_faces || loose_vertices;
  }
};

struct EncodeStats {
  RepairReport repair;
  std::size_t input_faces = 0;
  std::size_t base_faces = 0;
  std::size_t base_vertices = 0;
  std::size_t collapses = 0;
  // The loop ran without its measured distance: EncodeOptions::fast, or fast_from reached.
  bool fast = false;
};

// Recorded errors are float32 distances between points of the mesh, so at most its
// bounding-box diagonal: encode() refuses a wider mesh, whose errors could overflow.
inline constexpr double kMaxEncodeDiagonal = 1e38;

// Errors: kInvalidArgument for an option out of range or a mesh that is not well formed
// (arrays of the wrong length, a vertex or attribute index out of range, a coordinate that
// is not finite: validate_attributes()); kEmptyMesh (no vertices); kResourceLimit from 2^30
// vertices or faces, when the bounding-box diagonal exceeds kMaxEncodeDiagonal, or when
// memory runs out (on any of its threads). Never throws.
[[nodiscard]] Status encode(const Mesh& input, const EncodeOptions& options, ProgressiveMesh& out,
              EncodeStats* stats = nullptr);
// The same, for a stream to be written with `stream` (write_pm): the splits' layers stay
// inside its chunks (WriteOptions::chunk_splits, the one source of that size; the overload
// above uses WriteOptions{}'s). Its other fields do not matter here. Errors: those above, and
// kInvalidArgument for chunk_splits outside 1..2^20 when the splits are layered.
[[nodiscard]] Status encode(const Mesh& input, const EncodeOptions& options,
                            const WriteOptions& stream, ProgressiveMesh& out,
                            EncodeStats* stats = nullptr);
// The same two, taking the input: encode() lets the input's arrays go as soon as its collapse
// loop holds its own copy of them (the triangles, positions and corner attribute indices), so
// that the two are not held together where memory peaks (pmenc, which reads a mesh to
// encode it, no more; on a 950K-face textured mesh 40 MB less). The progressive mesh is the
// one the overloads above make of it; `input` is left empty (a default Mesh) whatever the
// outcome. Errors: as above.
[[nodiscard]] Status encode(Mesh&& input, const EncodeOptions& options, ProgressiveMesh& out,
                            EncodeStats* stats = nullptr);
[[nodiscard]] Status encode(Mesh&& input, const EncodeOptions& options,
                            const WriteOptions& stream, ProgressiveMesh& out,
                            EncodeStats* stats = nullptr);

}  // namespace pm
