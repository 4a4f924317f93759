// The progressive meshes the runtime and decode benchmarks compare, made once and cached
// (encoding a million faces takes minutes either way): ours by pm::encode, OpenMesh's by its
// Decimater with ModProgMeshT; and OpenMesh's .pm file, read and loaded as its ProgViewer
// does. Failures end the program with a message (benchmarks, not the library).
#pragma once

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <cstddef>
#include <string>
#include <vector>

#include "big_mesh.h"  // read_file, write_file_atomically
#include "pm/mesh.h"
#include "pm/progressive_mesh.h"

namespace pm::bench {

using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;

// Prints "program: message" to stderr and exits with status 1.
[[noreturn]] void fail(const std::string& message);

// The input's identity for the caches: its arrays' bytes.
std::string mesh_key(const pm::Mesh& mesh);
// The library's source, so that a cached .pm is encoded again when the encoder changes: the
// git tree of lib/ at HEAD, and a hash of its uncommitted changes when there are some.
std::string library_key();

struct OurSetup {
  std::string path;
  double encode_seconds = -1;  // -1: read from the cache
};

// Ours, default options as pmenc encodes, cached in `cache` (a fast zstd level: a cache,
// not a deliverable). `name` names the file.
pm::ProgressiveMesh our_progressive_mesh(const pm::Mesh& mesh, const std::string& name,
                                         const std::string& cache, OurSetup& setup);

// ModProgMeshT::write()'s file (OpenMesh/Tools/Decimater/ModProgMeshT_impl.hh), little
// endian: "ProgMesh", base vertex, base face and record counts (uint32), base positions
// (3 float32 each), base faces (3 uint32 each), then per vertex split, coarse to fine, the
// position of the vertex it creates (v0, 3 float32) and v1, vl, vr (uint32, -1 for none).
// v0 is vertex base + i of record i.
struct OpenMeshPm {
  struct Record {
    OMesh::Point p0;
    int v1, vl, vr;
  };
  std::vector<OMesh::Point> base_points;
  std::vector<uint32_t> base_faces;
  std::vector<Record> records;
  std::vector<std::size_t> faces_at;  // faces after the first k records

  std::size_t full_vertices() const { return base_points.size() + records.size(); }
  std::size_t full_faces() const { return faces_at.back(); }
  // The coarsest level with at least n faces, as pm::level_for_faces.
  std::size_t level_for_faces(std::size_t n) const {
    const auto it = std::lower_bound(faces_at.begin(), faces_at.end(), n);
    return it == faces_at.end() ? records.size() : std::size_t(it - faces_at.begin());
  }
};

bool parse_openmesh_pm(const std::string& bytes, OpenMeshPm& pm, std::string& problem);

// As the quality benchmark builds it: faces the half-edge mesh refuses (complex edges or
// vertices) on their own copies of their vertices, as OpenMesh's readers do.
OMesh to_openmesh(const pm::Mesh& mesh);

struct OpenMeshSetup {
  std::string path;
  double decimate_seconds = -1;  // -1: read from the cache
};

// OpenMesh's decimater to the end (no target: until no collapse is legal) with ModQuadricT
// as the priority, ModNormalFlippingT at 90 degrees (pmenc's own rule, as in quality.md's
// variant) and ModProgMeshT recording the collapses, whose write() makes the .pm. Cached.
OpenMeshPm openmesh_progressive_mesh(const pm::Mesh& mesh, const std::string& name,
                                     const std::string& cache, OpenMeshSetup& setup);

// The base mesh into a TriMesh, as ProgViewer's open_prog_mesh does; reserved for the
// full mesh, which ProgViewer does not do: it spares OpenMesh's replay the vectors' growth.
void load_base(const OpenMeshPm& pm, OMesh& mesh);

}  // namespace pm::bench
