// The encoder's entry point: checks the options and the attributes, runs the collapse
// loop (simplifier.cpp; through the manifold repair by cutting, manifold_repair.cpp,
// when the input is not a manifold already), and assembles its collapses, last first, into
// the vertex splits of a progressive mesh (Hoppe 1996, "Progressive meshes", §3).
#include <algorithm>
#include <cmath>
#include <functional>
#include <new>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "core/memory_pages.h"
#include "io/openmesh_logs.h"
#include "pm/advanced/stream_order.h"
#include "pm/encoder.h"
#include "pm/pm_codec.h"
#include "simplify/collapse_sequence.h"
#include "simplify/corner_attributes.h"
#include "simplify/manifold_repair.h"
#include "simplify/simplifier.h"

namespace pm {
namespace {

// Carried faces' corners straight from the input.
void copy_corners(const std::vector<uint32_t>& ids, uint32_t face, std::vector<uint32_t>& to) {
  to.insert(to.end(), ids.begin() + 3 * std::size_t{face}, ids.begin() + 3 * std::size_t{face} + 3);
}

// pmenc --keep-order: out.input_faces holds each input triangle's face id; make it
// 3 * face id + r, r the rotation that gives the input's first corner first. The faces'
// corners at full detail come from replaying the splits (Hoppe 1996, §3).
void record_face_rotations(const Mesh& input, ProgressiveMesh& out) {
  std::vector<uint32_t> corners = out.base_faces;
  for (std::size_t i = 0; i < out.splits.size(); ++i) {
    const VertexSplit& s = out.splits[i];
    const uint32_t v = out.base_vertex_count + static_cast<uint32_t>(i);
    for (uint32_t k = s.moved_begin; k < s.moved_begin + s.moved_count; ++k)
      for (int c = 0; c < 3; ++c)
        if (corners[3 * std::size_t{out.moved_faces[k]} + c] == s.u) corners[3 * std::size_t{out.moved_faces[k]} + c] = v;
    if (s.vl != kNoVertex) corners.insert(corners.end(), {v, s.u, s.vl});
    if (s.vr != kNoVertex) corners.insert(corners.end(), {s.u, v, s.vr});
  }
  corners.insert(corners.end(), out.carried_faces.begin(), out.carried_faces.end());
  // Each vertex id's input vertex: a welded copy stands for its canonical vertex's.
  std::vector<uint32_t> input_of(out.vertex_count(), kNoVertex);
  for (std::size_t i = 0; i < out.input_vertices.size(); ++i)
    input_of[out.input_vertices[i]] = static_cast<uint32_t>(i);
  for (const Weld& w : out.welds) input_of[w.copy] = input_of[w.canonical];
  for (std::size_t t = 0; t < out.input_faces.size(); ++t) {
    const uint32_t f = out.input_faces[t];
    const uint32_t* want = &input.triangles[3 * t];
    const uint32_t* have = &corners[3 * std::size_t{f}];
    uint32_t rotation = 0;
    for (uint32_t r = 0; r < 3; ++r) {
      if (input_of[have[r]] == want[0] && input_of[have[(r + 1) % 3]] == want[1] &&
          input_of[have[(r + 2) % 3]] == want[2]) {
        rotation = r;
        break;
      }
    }
    out.input_faces[t] = 3 * f + rotation;
  }
}

// What the collapse loop left: its collapses, the base mesh, and its points and counts
// (the repair's half-edge mesh may be gone: simplify clears it).
struct Simplified {
  const std::vector<Collapse>& collapses;
  const RecordList& moved_faces;
  const CollapseAttributes& attribute_record;
  const CornerAttributes* attributes;  // null: geometry only
  const BaseMesh& base;
  const float* points;  // three per loop vertex
  std::size_t n_vertices, n_faces;
};

// Numbers vertices and faces as the decoder will create them (base first, then one
// vertex and one or two faces per split, coarse to fine) and turns the collapses,
// last first, into vertex splits. `taken`: the input itself when encode(Mesh&&) gave it, whose
// attribute tables then move into `out` rather than being copied.
void assemble(const Mesh& input, const ManifoldMesh& repaired, const Simplified& run,
              bool keep_attributes, bool keep_order, ProgressiveMesh& out, Mesh* taken) {
  const std::size_t n_vertices = run.n_vertices, n_faces = run.n_faces;
  std::vector<uint32_t> vertex_id(n_vertices, kNoVertex);
  std::vector<uint32_t> face_id(n_faces, kNoVertex);
  out = ProgressiveMesh{};
  out.positions.reserve(3 * (n_vertices + repaired.loose_vertices.size()));
  std::vector<uint32_t> vertex_order;  // loop vertex of each vertex id
  vertex_order.reserve(n_vertices);
  auto add_position = [&](uint32_t v) {
    const float* p = run.points + 3 * std::size_t{v};
    out.positions.insert(out.positions.end(), {p[0], p[1], p[2]});
    vertex_order.push_back(v);
  };

  uint32_t next_vertex = 0, next_face = 0;
  for (uint32_t v : run.base.vertices) {
    vertex_id[v] = next_vertex++;
    add_position(v);
  }
  out.base_vertex_count = next_vertex;
  // Attributes: what each face has when it appears (Hoppe 1996, §3), base faces first.
  const CornerAttributes* attributes = run.attributes;
  const bool uvs = attributes && attributes->has_uvs();
  const bool normals = attributes && attributes->has_normals();
  const bool materials = attributes && attributes->has_materials();
  for (std::size_t i = 0; i < run.base.faces.size(); ++i) {
    const uint32_t f = run.base.faces[i];
    face_id[f] = next_face++;
    uint32_t at[3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t w = run.base.corners[3 * i + k];
      out.base_faces.push_back(vertex_id[w]);
      at[k] = w;
    }
    if (!attributes) continue;
    uint32_t uv[3], normal[3];
    attributes->corner_ids(f, at, uv, normal);
    if (uvs) out.face_uvs.insert(out.face_uvs.end(), uv, uv + 3);
    if (normals) out.face_normals.insert(out.face_normals.end(), normal, normal + 3);
    if (materials) out.face_materials.push_back(attributes->material(f));
  }
  const CollapseAttributes& record = run.attribute_record;

  const auto& collapses = run.collapses;
  out.splits.reserve(collapses.size());
  out.moved_faces.reserve(run.moved_faces.count());
  // Every array at its final size from the start: grown by doubling, each would be copied
  // to new memory several times over and held twice while it is (pmenc --fast on the
  // 950K-face textured mesh: about 10,000 of the process's 207,000 page faults).
  std::size_t face_count = run.base.faces.size() + repaired.carried_input_faces.size();
  for (const Collapse& c : collapses) face_count += (c.fl >= 0) + (c.fr >= 0);
  if (uvs) {
    out.face_uvs.reserve(3 * face_count);
    out.moved_uvs.reserve(run.moved_faces.count());
  }
  if (normals) {
    out.face_normals.reserve(3 * face_count);
    out.moved_normals.reserve(run.moved_faces.count());
  }
  if (materials) out.face_materials.reserve(face_count);
  // The collapses ahead name the vertices and faces they will look up, scattered over
  // the mesh: fetched that far ahead, the cache misses of several records overlap.
  constexpr std::size_t kFetchAhead = 16;
  for (std::size_t k = collapses.size(); k-- > 0;) {
    if (k >= kFetchAhead) {
      const Collapse& ahead = collapses[k - kFetchAhead];
      for (uint32_t vertex : {ahead.v, ahead.u, ahead.vl, ahead.vr}) {
        if (vertex != kNoVertex) __builtin_prefetch(vertex_id.data() + vertex);
      }
      if (ahead.moved_count > 0) {
        const uint32_t* moved = run.moved_faces.at(ahead.moved_begin);
        for (uint32_t i = 0; i < ahead.moved_count; ++i) __builtin_prefetch(face_id.data() + moved[i]);
      }
      for (const int face : {ahead.fl, ahead.fr}) {
        if (face >= 0) __builtin_prefetch(face_id.data() + face, 1);
      }
      __builtin_prefetch(run.points + 3 * std::size_t{ahead.v});
    }
    const Collapse* c = &collapses[k];
    vertex_id[c->v] = next_vertex++;
    add_position(c->v);
    VertexSplit split;
    split.u = vertex_id[c->u];
    split.vl = c->vl == kNoVertex ? kNoVertex : vertex_id[c->vl];
    split.vr = c->vr == kNoVertex ? kNoVertex : vertex_id[c->vr];
    split.error = c->bound;
    split.moved_begin = static_cast<uint32_t>(out.moved_faces.size());
    split.moved_count = c->moved_count;
    if (c->moved_count > 0) {
      const uint32_t* moved = run.moved_faces.at(c->moved_begin);
      for (uint32_t i = 0; i < c->moved_count; ++i) out.moved_faces.push_back(face_id[moved[i]]);
    }
    if (c->fl >= 0) face_id[c->fl] = next_face++;
    if (c->fr >= 0) face_id[c->fr] = next_face++;
    out.splits.push_back(split);
    const uint32_t added = (c->fl >= 0) + (c->fr >= 0);
    // A collapse's entries lie in one block of each list (record_list.h).
    auto copy = [](const RecordList& from, uint32_t place, uint32_t count,
                   std::vector<uint32_t>& to) {
      if (count == 0) return;
      const uint32_t* entries = from.at(place);
      to.insert(to.end(), entries, entries + count);
    };
    if (uvs) {
      copy(record.moved_uvs, c->moved_begin, c->moved_count, out.moved_uvs);
      copy(record.new_face_uvs, 3 * c->new_faces_begin, 3 * added, out.face_uvs);
    }
    if (normals) {
      copy(record.moved_normals, c->moved_begin, c->moved_count, out.moved_normals);
      copy(record.new_face_normals, 3 * c->new_faces_begin, 3 * added, out.face_normals);
    }
    if (materials) {
      if (c->fl >= 0) out.face_materials.push_back(attributes->material(static_cast<uint32_t>(c->fl)));
      if (c->fr >= 0) out.face_materials.push_back(attributes->material(static_cast<uint32_t>(c->fr)));
    }
  }

  for (uint32_t v = 0; v < n_vertices; ++v)
    if (repaired.canonical[v] != v)
      out.welds.push_back({vertex_id[v], vertex_id[repaired.canonical[v]]});
  for (uint32_t v : repaired.carried_faces) out.carried_faces.push_back(vertex_id[v]);
  for (uint32_t v : repaired.loose_vertices)
    out.positions.insert(out.positions.end(), input.positions.begin() + 3 * v,
                         input.positions.begin() + 3 * v + 3);
  out.loose_vertex_count = static_cast<uint32_t>(repaired.loose_vertices.size());

  // Carried faces keep the input's corners as they are, at every level.
  for (uint32_t f : repaired.carried_input_faces) {
    if (uvs) copy_corners(input.uv_indices, f, out.face_uvs);
    if (normals) copy_corners(input.normal_indices, f, out.face_normals);
    if (materials) out.face_materials.push_back(input.face_materials[f]);
  }
  if (keep_order) {
    // Each input vertex is one canonical loop vertex, or a loose vertex; each input
    // triangle one loop face, or a carried face (last in creation order).
    out.input_vertices.assign(input.vertex_count(), kNoVertex);
    for (uint32_t x = 0; x < n_vertices; ++x) {
      if (repaired.canonical[x] == x) out.input_vertices[repaired.input_vertex[x]] = vertex_id[x];
    }
    const uint32_t first_loose = next_vertex;
    for (std::size_t k = 0; k < repaired.loose_vertices.size(); ++k) {
      out.input_vertices[repaired.loose_vertices[k]] = first_loose + static_cast<uint32_t>(k);
    }
    out.input_faces.assign(input.face_count(), kNoVertex);
    for (uint32_t f = 0; f < n_faces; ++f) {
      if (face_id[f] != kNoVertex) out.input_faces[repaired.input_face[f]] = face_id[f];
    }
    for (std::size_t k = 0; k < repaired.carried_input_faces.size(); ++k) {
      out.input_faces[repaired.carried_input_faces[k]] = next_face + static_cast<uint32_t>(k);
    }
  }
  if (keep_order) record_face_rotations(input, out);
  // Last: the loop's corner records point into these tables until here.
  const auto table = [&](std::vector<float> Mesh::*values) -> std::vector<float> {
    if (taken) return std::move(taken->*values);
    return input.*values;
  };
  if (uvs) out.uvs = table(&Mesh::uvs);
  if (normals) out.normals = table(&Mesh::normals);
  if (keep_attributes) {
    out.material_names = input.material_names;
    out.material_libraries = input.material_libraries;
    if (input.has_colors()) {
      // Per vertex id, like positions: each vertex takes its input vertex's colour.
      const std::size_t cc = input.color_components;
      out.color_components = input.color_components;
      out.colors.reserve(cc * out.vertex_count());
      auto add_color = [&](uint32_t input_vertex) {
        out.colors.insert(out.colors.end(), input.colors.begin() + cc * input_vertex,
                          input.colors.begin() + cc * (input_vertex + 1));
      };
      for (uint32_t x : vertex_order) add_color(repaired.input_vertex[x]);
      for (uint32_t v : repaired.loose_vertices) add_color(v);
    }
  }
}

}  // namespace

double default_feature_angle(Metric metric) {
  return metric == Metric::kQuadric ? 180.0 : 30.0;
}

double effective_feature_angle(const EncodeOptions& options) {
  return options.feature_angle_deg < 0 ? default_feature_angle(options.metric)
                                       : options.feature_angle_deg;
}

namespace {

// `taken`: the input itself when encode(Mesh&&) gave it (its arrays may go as soon as nothing
// reads them), else null.
Status encode_unguarded(const Mesh& input, const EncodeOptions& options, uint32_t chunk_splits,
                        ProgressiveMesh& out, EncodeStats* stats, Mesh* taken,
                        const LoopSwitches& switches = {}) {
  if (!(options.feature_angle_deg <= 180))  // negative: the default; NaN fails here
    return Status(ErrorCode::kInvalidArgument, "feature angle must be within [0, 180] degrees");
  if (!(options.max_normal_flip_deg >= 0 && options.max_normal_flip_deg <= 180))
    return Status(ErrorCode::kInvalidArgument, "normal flip limit must be within [0, 180] degrees");
  if (!(options.layer_window >= 0))  // NaN fails here; infinity: whole chunks
    return Status(ErrorCode::kInvalidArgument, "layer window must be a share >= 0");
  if (options.layer_window > 0 && chunk_splits == 0)
    return Status(ErrorCode::kInvalidArgument, "layer chunks must hold at least one split");

  if (Status valid = validate_attributes(input); !valid)
    return Status(valid.code(), "mesh attributes: " + valid.message());
  if (!options.drop_attributes) {
    if (Status s = check_material_strings(input.material_names, input.material_libraries); !s)
      return s;
  }

  // Stage 1: the collapse sequence, on the input as it is when it is a manifold, else on
  // the repair's manifold mesh. Stage 2: the progressive mesh. (EncodeOptions::fast: the
  // same loop without its measured distance.)
  if (Status s = check_encodable(input); !s) return s;
  const std::size_t input_faces = input.face_count();
  ManifoldMesh repaired;
  // encode(Mesh&&): once the loop holds its own copies, the input's arrays that nothing reads
  // afterwards go, so that they and the loop's state are not held together where memory
  // peaks. assemble() still reads the triangles for --keep-order's rotations, the positions
  // of loose vertices, the corners of carried faces, and the tables (uvs, normals, colours).
  const auto release_input = [&] {
    if (!taken) return;
    const auto release = [](auto& values) { std::remove_reference_t<decltype(values)>().swap(values); };
    if (!options.keep_order) {
      release(taken->triangles);
      if (repaired.loose_vertices.empty()) release(taken->positions);
    }
    if (repaired.carried_input_faces.empty()) {
      release(taken->uv_indices);
      release(taken->normal_indices);
      release(taken->face_materials);
    }
  };
  {
    // The loop's state ends here, before layer_splits() and validate() take their own
    // memory.
    Simplification run;
    const std::size_t n_vertices = input.vertex_count(), n_faces = input_faces;
    if (simplify_direct(input, options, run, switches, release_input)) {
      repaired.input_vertex.resize(n_vertices);
      std::iota(repaired.input_vertex.begin(), repaired.input_vertex.end(), uint32_t{0});
      repaired.canonical = repaired.input_vertex;
      repaired.pinned.assign(n_vertices, 0);
      repaired.input_face.resize(n_faces);
      std::iota(repaired.input_face.begin(), repaired.input_face.end(), uint32_t{0});
    } else {
      if (Status s = build_manifold_mesh(input, repaired); !s) return s;
      if (Status s = simplify(input, repaired, options, run, switches, release_input); !s)
        return s;
    }
    assemble(input, repaired,
             Simplified{run.collapses, run.moved_faces, run.attribute_record,
                        run.attributes.get(), run.base, run.points.data(),
                        run.points.size() / 3, repaired.input_face.size()},
             !options.drop_attributes, options.keep_order, out, taken);
  }
  detail::return_free_memory();  // the loop's, before layer_splits() copies the splits
  // The progressive mesh, checked as a decoder would check it.
  if (options.layer_window > 0)
    layer_splits(out, chunk_splits, options.layer_window, options.threads);
  order_attribute_tables(out);  // after the splits' order is final
  if (Status valid = validate(out); !valid)
    return Status(ErrorCode::kInternal, "encoder produced " + valid.message());

  if (stats) {
    stats->repair = repaired.report;
    stats->input_faces = input_faces;
    stats->base_faces = out.base_face_count();
    stats->base_vertices = out.base_vertex_count;
    stats->collapses = out.splits.size();
    stats->fast = options.fast;
  }
  if (options.progress) options.progress(1.0);
  return Status::ok();
}

}  // namespace

Status encode_with_switches(const Mesh& input, const EncodeOptions& options,
                            const LoopSwitches& switches, ProgressiveMesh& out) {
  return encode_unguarded(input, options, WriteOptions{}.chunk_splits, out, nullptr, nullptr,
                          switches);
}

Status encode(const Mesh& input, const EncodeOptions& options, ProgressiveMesh& out,
              EncodeStats* stats) {
  return encode(input, options, WriteOptions{}, out, stats);
}

namespace {

Status encode_guarded(const Mesh& input, const EncodeOptions& options, const WriteOptions& stream,
                      ProgressiveMesh& out, EncodeStats* stats, Mesh* taken) {
  // OpenMesh's logs are off while the repair's half-edge mesh is built and read, as the caller
  // left them afterwards; no exception leaves (status.h).
  const QuietOpenMeshLogs quiet;
  try {
    // fast_from: the one place the rule is (pmenc and pmesh pass their --fast-from here).
    if (!options.fast && options.fast_from != 0 && input.face_count() >= options.fast_from) {
      EncodeOptions fast = options;
      fast.fast = true;
      return encode_unguarded(input, fast, stream.chunk_splits, out, stats, taken);
    }
    return encode_unguarded(input, options, stream.chunk_splits, out, stats, taken);
  } catch (const std::bad_alloc&) {
    out = ProgressiveMesh();
    return Status(ErrorCode::kResourceLimit, "out of memory");
  } catch (const std::length_error&) {  // a container asked for more than it can hold
    out = ProgressiveMesh();
    return Status(ErrorCode::kResourceLimit, "out of memory");
  }
}

}  // namespace

Status encode(const Mesh& input, const EncodeOptions& options, const WriteOptions& stream,
              ProgressiveMesh& out, EncodeStats* stats) {
  return encode_guarded(input, options, stream, out, stats, nullptr);
}

Status encode(Mesh&& input, const EncodeOptions& options, ProgressiveMesh& out,
              EncodeStats* stats) {
  return encode(std::move(input), options, WriteOptions{}, out, stats);
}

Status encode(Mesh&& input, const EncodeOptions& options, const WriteOptions& stream,
              ProgressiveMesh& out, EncodeStats* stats) {
  Mesh taken = std::move(input);
  input = Mesh();  // empty whatever the outcome, as encoder.h says
  return encode_guarded(taken, options, stream, out, stats, &taken);
}

}  // namespace pm
