// Batches of independent vertex splits (issue 5): within each chunk of the .pm stream, the
// splits are reordered into layers of splits that do not depend on each other, each layer in
// the order of u's id, so that the writer can code u as a small gap from the previous u of
// its layer instead of a global vertex id (Pajarola and Rossignac 2000, "Compressed
// progressive meshes", §3: a batch of independent splits marks its split vertices among the
// current ones, about log2(n/k) bits per split rather than log2(n)).
//
// Why this is safe. Two splits A (earlier) and B conflict when B's u is among the vertices A
// touches (A's u, v, vl, vr and the vertices of A's moved faces), or A's u is among B's, or
// B touches A's new vertex v. Splits that do not conflict act on disjoint fans: neither
// changes a face around the other's u, nor creates a vertex or face the other names, so they
// commute, and any order that keeps each conflicting pair in its original order (a layer is
// 1 + the largest layer of the earlier splits of the chunk it conflicts with) refines to the
// same mesh at the end of every chunk. Each split keeps its v's position, attributes and
// moved corners; vertex and face ids are renumbered to the new creation order everywhere.
//
// Errors: a split's error bounds the mesh before it. Along the original order the errors
// are non-increasing, so the error before split k is the largest error of the splits not yet
// applied; in the new order each split takes exactly that (the largest original error from
// it to the end of its chunk), which is non-increasing again, equal to the chunk's first
// error at its start, and the same as before at every chunk boundary (the chunk index's
// error_after does not change).
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "pm/progressive_mesh.h"

namespace pm {

std::vector<uint32_t> chunk_plan(uint32_t splits, uint32_t largest) {
  std::vector<uint32_t> sizes;
  if (largest == 0) largest = 1;
  uint32_t size = std::min<uint32_t>(256, largest);
  for (uint32_t done = 0; done < splits;) {
    const uint32_t n = std::min(size, splits - done);
    sizes.push_back(n);
    done += n;
    if (size < largest) size = std::min(largest, size * 2);
  }
  return sizes;
}

std::vector<uint32_t> layer_windows(uint32_t base_vertices, uint32_t splits, uint32_t largest_chunk,
                                    double share) {
  std::vector<uint32_t> windows;
  uint64_t done = 0;
  for (const uint32_t chunk : chunk_plan(splits, largest_chunk)) {
    for (uint32_t left = chunk; left > 0;) {
      uint32_t size = left;
      if (share > 0 && std::isfinite(share)) {
        const double most = std::floor(share * static_cast<double>(base_vertices + done));
        size = static_cast<uint32_t>(std::clamp(most, double{kLeastLayerWindow}, double{left}));
      }
      windows.push_back(size);
      left -= size;
      done += size;
    }
  }
  return windows;
}

void layer_splits(ProgressiveMesh& pm, uint32_t largest_chunk, double share) {
  const std::size_t S = pm.splits.size();
  if (S < 2) return;
  const uint32_t B = pm.base_vertex_count;
  const std::size_t vertex_count = pm.vertex_count();
  const std::size_t base_faces = pm.base_face_count();
  std::size_t split_faces = 0;
  for (const VertexSplit& s : pm.splits) split_faces += s.new_face_count();
  const std::size_t carried = pm.carried_faces.size() / 3;
  const std::size_t total_faces = base_faces + split_faces + carried;

  // Corners of the current level, in the original order and ids (to know the vertices of
  // each split's moved faces when it is applied).
  std::vector<uint32_t> corners(pm.base_faces);
  corners.reserve(3 * (base_faces + split_faces));

  // Old -> new ids. Vertices and faces before the chunk being processed are final.
  std::vector<uint32_t> vertex_map(vertex_count);
  std::iota(vertex_map.begin(), vertex_map.end(), 0u);
  std::vector<uint32_t> face_map(total_faces);
  std::iota(face_map.begin(), face_map.end(), 0u);
  // Old face id -> first new-face index of each split (original order).
  std::vector<std::size_t> first_face(S);

  // Per vertex (old ids): the largest layer + 1 of a split of this chunk that touches it
  // (X) or whose u or v it is (UV); stamped by chunk.
  std::vector<uint32_t> in_x(vertex_count, 0), in_uv(vertex_count, 0);
  std::vector<uint32_t> stamp_x(vertex_count, 0), stamp_uv(vertex_count, 0);

  std::vector<VertexSplit> new_splits(S);
  std::vector<uint32_t> new_moved;
  new_moved.reserve(pm.moved_faces.size());
  std::vector<uint32_t> new_moved_uvs, new_moved_normals;
  std::vector<float> new_positions(pm.positions);
  std::vector<float> new_colors(pm.colors);
  const std::size_t cc = pm.color_components;
  std::vector<uint32_t> new_face_uvs(pm.face_uvs), new_face_normals(pm.face_normals);
  std::vector<uint32_t> new_face_materials(pm.face_materials);

  std::vector<uint32_t> layer(S), touched;
  std::size_t begin = 0, face_cursor = base_faces;
  uint32_t chunk_number = 0;  // the window's number
  for (const uint32_t size : layer_windows(B, static_cast<uint32_t>(S), largest_chunk, share)) {
    ++chunk_number;
    const std::size_t end = begin + size;
    const std::size_t chunk_face_begin = face_cursor;
    // Layers, replaying the chunk in its original order.
    for (std::size_t i = begin; i < end; ++i) {
      const VertexSplit& s = pm.splits[i];
      const uint32_t v = B + static_cast<uint32_t>(i);
      touched.assign({s.u, v});
      if (s.vl != kNoVertex) touched.push_back(s.vl);
      if (s.vr != kNoVertex) touched.push_back(s.vr);
      for (uint32_t k = s.moved_begin; k < s.moved_begin + s.moved_count; ++k) {
        const uint32_t* f = &corners[3 * std::size_t{pm.moved_faces[k]}];
        touched.insert(touched.end(), f, f + 3);
      }
      uint32_t depth = stamp_x[s.u] == chunk_number ? in_x[s.u] : 0;
      for (uint32_t w : touched) {
        if (stamp_uv[w] == chunk_number) depth = std::max(depth, in_uv[w]);
      }
      layer[i] = depth;  // 0-based
      for (uint32_t w : touched) {
        if (stamp_x[w] != chunk_number) stamp_x[w] = chunk_number, in_x[w] = 0;
        in_x[w] = std::max(in_x[w], depth + 1);
      }
      for (uint32_t w : {s.u, v}) {
        if (stamp_uv[w] != chunk_number) stamp_uv[w] = chunk_number, in_uv[w] = 0;
        in_uv[w] = std::max(in_uv[w], depth + 1);
      }
      // Apply (original ids).
      for (uint32_t k = s.moved_begin; k < s.moved_begin + s.moved_count; ++k) {
        uint32_t* f = &corners[3 * std::size_t{pm.moved_faces[k]}];
        for (int c = 0; c < 3; ++c)
          if (f[c] == s.u) f[c] = v;
      }
      first_face[i] = face_cursor;
      if (s.vl != kNoVertex) corners.insert(corners.end(), {v, s.u, s.vl}), ++face_cursor;
      if (s.vr != kNoVertex) corners.insert(corners.end(), {s.u, v, s.vr}), ++face_cursor;
    }
    // The new order: by layer, then by u's new id (known for the earlier layers when a
    // layer is sorted, since a split's u is never the v of a split of its own layer).
    std::vector<std::size_t> order(size);
    std::iota(order.begin(), order.end(), begin);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return layer[a] < layer[b]; });
    std::size_t at = 0;
    uint32_t next_vertex = B + static_cast<uint32_t>(begin);
    std::size_t next_face = chunk_face_begin;
    while (at < order.size()) {
      std::size_t stop = at;
      while (stop < order.size() && layer[order[stop]] == layer[order[at]]) ++stop;
      std::stable_sort(order.begin() + at, order.begin() + stop, [&](std::size_t a, std::size_t b) {
        return vertex_map[pm.splits[a].u] < vertex_map[pm.splits[b].u];
      });
      for (std::size_t k = at; k < stop; ++k) {
        const std::size_t i = order[k];
        vertex_map[B + i] = next_vertex++;
        std::size_t f = first_face[i];
        for (uint32_t n = 0; n < pm.splits[i].new_face_count(); ++n)
          face_map[f++] = static_cast<uint32_t>(next_face++);
      }
      at = stop;
    }
    // Error before each split in the new order: the largest original error from it on.
    float suffix_max = 0.0f;
    for (std::size_t k = size; k-- > 0;) {
      suffix_max = std::max(suffix_max, pm.splits[order[k]].error);
      layer[order[k]] = 0;  // reuse: not needed any more
      new_splits[begin + k].error = suffix_max;
    }
    for (std::size_t k = 0; k < size; ++k) {
      const std::size_t i = order[k];
      const VertexSplit& s = pm.splits[i];
      VertexSplit& t = new_splits[begin + k];
      const uint32_t old_v = B + static_cast<uint32_t>(i),
                     new_v = B + static_cast<uint32_t>(begin + k);
      t.u = vertex_map[s.u];
      t.vl = s.vl == kNoVertex ? kNoVertex : vertex_map[s.vl];
      t.vr = s.vr == kNoVertex ? kNoVertex : vertex_map[s.vr];
      t.moved_begin = static_cast<uint32_t>(new_moved.size());
      t.moved_count = s.moved_count;
      for (uint32_t m = s.moved_begin; m < s.moved_begin + s.moved_count; ++m) {
        new_moved.push_back(face_map[pm.moved_faces[m]]);
        if (!pm.moved_uvs.empty()) new_moved_uvs.push_back(pm.moved_uvs[m]);
        if (!pm.moved_normals.empty()) new_moved_normals.push_back(pm.moved_normals[m]);
      }
      std::copy_n(pm.positions.begin() + 3 * std::size_t{old_v}, 3,
                  new_positions.begin() + 3 * std::size_t{new_v});
      if (cc != 0) std::copy_n(pm.colors.begin() + cc * old_v, cc, new_colors.begin() + cc * new_v);
      for (uint32_t n = 0; n < s.new_face_count(); ++n) {
        const std::size_t from = first_face[i] + n, to = face_map[from];
        if (!pm.face_uvs.empty())
          std::copy_n(pm.face_uvs.begin() + 3 * from, 3, new_face_uvs.begin() + 3 * to);
        if (!pm.face_normals.empty())
          std::copy_n(pm.face_normals.begin() + 3 * from, 3, new_face_normals.begin() + 3 * to);
        if (!pm.face_materials.empty()) new_face_materials[to] = pm.face_materials[from];
      }
    }
    begin = end;
  }
  pm.splits = std::move(new_splits);
  pm.moved_faces = std::move(new_moved);
  if (!pm.moved_uvs.empty()) pm.moved_uvs = std::move(new_moved_uvs);
  if (!pm.moved_normals.empty()) pm.moved_normals = std::move(new_moved_normals);
  pm.positions = std::move(new_positions);
  pm.colors = std::move(new_colors);
  pm.face_uvs = std::move(new_face_uvs);
  pm.face_normals = std::move(new_face_normals);
  pm.face_materials = std::move(new_face_materials);
  for (Weld& w : pm.welds) w.copy = vertex_map[w.copy], w.canonical = vertex_map[w.canonical];
  for (uint32_t& v : pm.carried_faces) v = vertex_map[v];
  for (uint32_t& v : pm.input_vertices) v = vertex_map[v];
  for (uint32_t& f : pm.input_faces) f = 3 * face_map[f / 3] + f % 3;
}

}  // namespace pm
