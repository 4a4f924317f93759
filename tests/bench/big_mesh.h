// Large test meshes for the benchmarks: a shared mesh made finer by Loop subdivision (Loop
// 1987, "Smooth subdivision surfaces based on triangles", through OpenMesh's LoopT), so that
// the runtime (issue 6) and whole-process (issue 10) benchmarks run on 1 to 4 million faces
// of a real shape. Each subdivision step splits every triangle into four:
//
//   stanford-bunny.obj, 2 steps:  1,111,216 faces (the "~1M-face" mesh)
//   nefertiti.obj,      2 steps:  1,599,008 faces
//   stanford-bunny.obj, 3 steps:  4,444,864 faces
//
// A subdivided mesh takes seconds to make, so load_subdivided() keeps it as binary PLY
// (float32, read back bit for bit) in a cache directory and reuses it when the source file
// is unchanged.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "pm/mesh.h"
#include "pm/status.h"

namespace pm::bench {

// The mesh after `times` steps of Loop subdivision (0: a copy of its geometry). Positions
// and triangles only: attributes are dropped, as the subdivided surface has no seams to
// carry them along. Vertices no face uses are dropped too (LoopT would leave them at an
// undefined position). A face OpenMesh's half-edge mesh refuses (a complex edge or
// vertex) is given its own copies of its vertices, as OpenMesh's readers do; it is then
// subdivided as a separate patch; refused_faces (when not null) gets their number. Vertex
// ids of the result are OpenMesh's.
Mesh loop_subdivide(const Mesh& mesh, int times, std::size_t* refused_faces = nullptr);

// `times` steps of Loop subdivision that keep every attribute (the textured ~1M-face mesh of
// issue 25's whole-process benchmark): positions move as Loop's rules say (Loop 1987, §3.1:
// an edge point 3/8 of its ends plus 1/8 of the two opposite corners, a vertex (1 - nβ) of
// itself plus β of each neighbour, β = (5/8 - (3/8 + cos(2π/n)/4)²)/n; on a boundary the
// midpoint and 3/4 + 1/8 + 1/8 of the boundary neighbours; an edge of three or more faces,
// or a vertex where the boundary is not one curve, stays linear), while the corner
// attributes are interpolated linearly inside each face's own triangle of values: the new
// corner at an edge's midpoint takes the mean of that face's two uv (and normal) entries,
// shared with the face across the edge only when both faces use the same two entries. A UV
// seam or a crease therefore stays one, along the whole subdivided edge. Colours (per
// vertex) are averaged at edge points, materials go to the face's four children. Vertex ids
// 0..V-1 keep their vertices; faces keep their order (each parent's four children together).
// No OpenMesh (a half-edge mesh would refuse the seams' faces on a non-manifold input and
// renumber the corners): a few hundred milliseconds for a million faces.
Mesh loop_subdivide_keeping_attributes(const Mesh& mesh, int times);

// The shared test meshes: PM_BENCH_SOURCE_DIR/../shared/meshes, the folder next to the
// repository (see its README.md).
std::string shared_meshes_dir();
// A whole file into `bytes`; false when it cannot be read.
bool read_file(const std::string& path, std::string& bytes);
// Written beside `path` and renamed, so that a killed run never leaves a partial file.
bool write_file_atomically(const std::string& path, const std::string& bytes);
// Where load_subdivided() keeps its results by default: big_meshes/ in this build's
// tests/bench directory.
std::string default_cache_dir();

// 64-bit FNV-1a of some bytes: the cache keys of the benchmarks (not cryptographic; it tells
// a changed input from the one a cached result was made from).
uint64_t fnv1a64(const std::string& bytes);
// The key as 16 hexadecimal digits.
std::string hex64(uint64_t value);

// Reads `path` (a shared mesh, or any mesh file) and subdivides it `times` times. The result
// is cached in cache_dir (created when missing; "" for no cache) as
// STEM-loopTIMES-SIZE-HASH.ply, keyed by the source file's size and hash, so a rerun reads
// it back in a second instead of subdividing again. Progress goes to stderr unless quiet.
// Errors: those of read_mesh on the source; a cache that cannot be written is reported on
// stderr and skipped.
Status load_subdivided(const std::string& path, int times, const std::string& cache_dir, Mesh& out,
                       bool quiet = false);

}  // namespace pm::bench
