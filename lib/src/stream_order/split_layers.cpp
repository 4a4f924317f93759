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
#include <condition_variable>
#include <exception>
#include <mutex>
#include <numeric>
#include <thread>
#include <utility>
#include <vector>

#include "core/in_turn.h"
#include "pm/advanced/stream_order.h"
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
        size = static_cast<uint32_t>(
            std::clamp(most, static_cast<double>(kLeastLayerWindow), static_cast<double>(left)));
      }
      windows.push_back(size);
      left -= size;
      done += size;
    }
  }
  return windows;
}

void layer_splits(ProgressiveMesh& pm, uint32_t largest_chunk, double share, unsigned threads) {
  const std::size_t S = pm.splits.size();
  if (S < 2) return;
  const uint32_t B = pm.base_vertex_count;
  const std::size_t vertex_count = pm.vertex_count();
  const std::size_t base_faces = pm.base_face_count();
  // Each split's first new face (original order and ids), and the faces in all.
  std::vector<std::size_t> first_face(S + 1);
  first_face[0] = base_faces;
  uint32_t most_moved = 0;
  for (std::size_t i = 0; i < S; ++i) {
    first_face[i + 1] = first_face[i] + pm.splits[i].new_face_count();
    most_moved = std::max(most_moved, pm.splits[i].moved_count);
  }
  const std::size_t split_faces = first_face[S] - base_faces;
  const std::size_t carried = pm.carried_faces.size() / 3;
  const std::size_t total_faces = base_faces + split_faces + carried;
  const std::vector<uint32_t> windows =
      layer_windows(B, static_cast<uint32_t>(S), largest_chunk, share);
  std::vector<std::size_t> window_begin(windows.size() + 1, 0);
  for (std::size_t w = 0; w < windows.size(); ++w)
    window_begin[w + 1] = window_begin[w] + windows[w];
  const uint32_t largest_window = *std::max_element(windows.begin(), windows.end());

  // Everything either stage below writes is allocated here, so that neither allocates (nor
  // throws) while the other runs on another thread.
  //
  // Stage 1, the layers (in window order; reads pm, writes corners, marks, layer):
  // Corners of the current level, in the original order and ids (to know the vertices of
  // each split's moved faces when it is applied).
  std::vector<uint32_t> corners(pm.base_faces);
  corners.reserve(3 * (base_faces + split_faces));
  // Per vertex (old ids), for the window `window`: the largest layer + 1 of a split of this
  // window that touches it (x) or whose u or v it is (uv). One record: one cache miss.
  struct Mark {
    uint32_t window = 0, x = 0, uv = 0;
  };
  std::vector<Mark> marks(vertex_count);
  constexpr std::size_t kFetchAhead = 16;  // splits
  std::vector<uint32_t> layer(S), touched;
  touched.reserve(4 + 3 * std::size_t{most_moved});
  const auto layer_window = [&](std::size_t w) {
    const auto number = static_cast<uint32_t>(w + 1);
    const auto mark = [&](uint32_t vertex) -> Mark& {
      Mark& m = marks[vertex];
      if (m.window != number) m = Mark{number, 0, 0};
      return m;
    };
    for (std::size_t i = window_begin[w]; i < window_begin[w + 1]; ++i) {
      // The splits ahead name the faces and vertices they will read: fetched now, the
      // cache misses of several splits overlap (each alone waits for memory).
      if (i + kFetchAhead < S) {
        const VertexSplit& ahead = pm.splits[i + kFetchAhead];
        for (uint32_t k = ahead.moved_begin; k < ahead.moved_begin + ahead.moved_count; ++k) {
          const std::size_t f = pm.moved_faces[k];
          if (3 * f < corners.capacity()) __builtin_prefetch(corners.data() + 3 * f, 1);
        }
        __builtin_prefetch(marks.data() + ahead.u, 1);
        if (ahead.vl != kNoVertex) __builtin_prefetch(marks.data() + ahead.vl, 1);
        if (ahead.vr != kNoVertex) __builtin_prefetch(marks.data() + ahead.vr, 1);
      }
      if (i + kFetchAhead / 2 < S) {  // the vertices of the faces fetched before
        const VertexSplit& ahead = pm.splits[i + kFetchAhead / 2];
        for (uint32_t k = ahead.moved_begin; k < ahead.moved_begin + ahead.moved_count; ++k) {
          const std::size_t f = pm.moved_faces[k];
          if (3 * f + 2 < corners.size()) {
            for (int c = 0; c < 3; ++c) __builtin_prefetch(marks.data() + corners[3 * f + c], 1);
          }
        }
      }
      const VertexSplit& s = pm.splits[i];
      const uint32_t v = B + static_cast<uint32_t>(i);
      touched.assign({s.u, v});
      if (s.vl != kNoVertex) touched.push_back(s.vl);
      if (s.vr != kNoVertex) touched.push_back(s.vr);
      for (uint32_t k = s.moved_begin; k < s.moved_begin + s.moved_count; ++k) {
        const uint32_t* f = &corners[3 * std::size_t{pm.moved_faces[k]}];
        touched.insert(touched.end(), f, f + 3);
      }
      uint32_t depth = mark(s.u).x;
      for (uint32_t t : touched) depth = std::max(depth, mark(t).uv);
      layer[i] = depth;  // 0-based
      for (uint32_t t : touched) {
        Mark& m = mark(t);
        m.x = std::max(m.x, depth + 1);
      }
      for (uint32_t t : {s.u, v}) {
        Mark& m = mark(t);
        m.uv = std::max(m.uv, depth + 1);
      }
      // Apply (original ids).
      for (uint32_t k = s.moved_begin; k < s.moved_begin + s.moved_count; ++k) {
        uint32_t* f = &corners[3 * std::size_t{pm.moved_faces[k]}];
        for (int c = 0; c < 3; ++c)
          if (f[c] == s.u) f[c] = v;
      }
      if (s.vl != kNoVertex) corners.insert(corners.end(), {v, s.u, s.vl});
      if (s.vr != kNoVertex) corners.insert(corners.end(), {s.u, v, s.vr});
    }
  };

  // Stage 2, the new order and ids (in window order, each window once stage 1 is done with
  // it; reads pm and layer, writes the maps and the new arrays).
  // Old -> new ids. Vertices and faces before the window being reordered are final.
  std::vector<uint32_t> vertex_map(vertex_count);
  std::iota(vertex_map.begin(), vertex_map.end(), 0u);
  std::vector<uint32_t> face_map(total_faces);
  std::iota(face_map.begin(), face_map.end(), 0u);
  std::vector<VertexSplit> new_splits(S);
  std::vector<uint32_t> new_moved;
  new_moved.reserve(pm.moved_faces.size());
  std::vector<uint32_t> new_moved_uvs, new_moved_normals;
  new_moved_uvs.reserve(pm.moved_uvs.size());
  new_moved_normals.reserve(pm.moved_normals.size());
  std::vector<float> new_positions(pm.positions);
  std::vector<float> new_colors(pm.colors);
  const std::size_t cc = pm.color_components;
  std::vector<uint32_t> new_face_uvs(pm.face_uvs), new_face_normals(pm.face_normals);
  std::vector<uint32_t> new_face_materials(pm.face_materials);
  // A window's splits (original index), by layer then by u's new id, and the sort keys.
  std::vector<uint32_t> order(largest_window), layer_start;
  std::vector<std::pair<uint32_t, uint32_t>> keyed(largest_window);
  layer_start.reserve(largest_window + 2);
  const auto reorder_window = [&](std::size_t w) {
    const std::size_t begin = window_begin[w], size = windows[w];
    // By layer (a counting sort, stable), then each layer by u's new id: known for the
    // earlier layers when a layer is sorted, since a split's u is never the v of a split of
    // its own layer.
    uint32_t layers = 0;
    for (std::size_t i = begin; i < begin + size; ++i) layers = std::max(layers, layer[i] + 1);
    layer_start.assign(layers + 1, 0);
    for (std::size_t i = begin; i < begin + size; ++i) ++layer_start[layer[i] + 1];
    for (uint32_t l = 0; l < layers; ++l) layer_start[l + 1] += layer_start[l];
    for (std::size_t i = begin; i < begin + size; ++i)
      order[layer_start[layer[i]]++] = static_cast<uint32_t>(i);  // now each layer's end
    uint32_t next_vertex = B + static_cast<uint32_t>(begin);
    auto next_face = static_cast<uint32_t>(first_face[begin]);
    for (uint32_t l = 0, at = 0; l < layers; ++l) {
      const uint32_t stop = layer_start[l];
      for (uint32_t k = at; k < stop; ++k) {
        if (k + kFetchAhead < stop) __builtin_prefetch(&pm.splits[order[k + kFetchAhead]]);
        if (k + kFetchAhead / 2 < stop)
          __builtin_prefetch(vertex_map.data() + pm.splits[order[k + kFetchAhead / 2]].u);
        keyed[k] = {vertex_map[pm.splits[order[k]].u], order[k]};
      }
      std::sort(keyed.begin() + at, keyed.begin() + stop);
      for (uint32_t k = at; k < stop; ++k) {
        const std::size_t i = keyed[k].second;
        order[k] = keyed[k].second;
        vertex_map[B + i] = next_vertex++;
        for (std::size_t f = first_face[i]; f < first_face[i + 1]; ++f) face_map[f] = next_face++;
      }
      at = stop;
    }
    // Error before each split in the new order: the largest original error from it on.
    float suffix_max = 0.0f;
    for (std::size_t k = size; k-- > 0;) {
      suffix_max = std::max(suffix_max, pm.splits[order[k]].error);
      new_splits[begin + k].error = suffix_max;
    }
    for (std::size_t k = 0; k < size; ++k) {
      if (k + kFetchAhead < size) __builtin_prefetch(&pm.splits[order[k + kFetchAhead]]);
      if (k + kFetchAhead / 2 < size) {  // what the split fetched before names
        const std::size_t i = order[k + kFetchAhead / 2];
        const VertexSplit& ahead = pm.splits[i];
        __builtin_prefetch(vertex_map.data() + ahead.u);
        if (ahead.vl != kNoVertex) __builtin_prefetch(vertex_map.data() + ahead.vl);
        if (ahead.vr != kNoVertex) __builtin_prefetch(vertex_map.data() + ahead.vr);
        for (uint32_t m = ahead.moved_begin; m < ahead.moved_begin + ahead.moved_count; ++m)
          __builtin_prefetch(face_map.data() + pm.moved_faces[m]);
        __builtin_prefetch(pm.positions.data() + 3 * (B + i));
      }
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
      for (std::size_t from = first_face[i]; from < first_face[i + 1]; ++from) {
        const std::size_t to = face_map[from];
        if (!pm.face_uvs.empty())
          std::copy_n(pm.face_uvs.begin() + 3 * from, 3, new_face_uvs.begin() + 3 * to);
        if (!pm.face_normals.empty())
          std::copy_n(pm.face_normals.begin() + 3 * from, 3, new_face_normals.begin() + 3 * to);
        if (!pm.face_materials.empty()) new_face_materials[to] = pm.face_materials[from];
      }
    }
  };

  // The two stages in a pipeline: stage 1 on a thread of its own a window ahead, stage 2
  // here (each is about half of the work; they share no array either writes). An exception
  // in either (out of memory) stops both and is rethrown here once the thread is joined, so
  // that it reaches encode(), which returns kResourceLimit, instead of std::terminate.
  constexpr std::size_t kPipelineSplits = std::size_t{1} << 16;
  const auto in_order = [&] {
    for (std::size_t w = 0; w < windows.size(); ++w) layer_window(w), reorder_window(w);
  };
  if (thread_count(threads) < 2 || S < kPipelineSplits) {
    in_order();
  } else {
    std::mutex mutex;
    std::condition_variable layered;
    std::size_t windows_layered = 0;
    std::exception_ptr first_failure, second_failure;
    bool stop = false;  // stage 2 failed: stage 1 need not go on
    std::thread first_stage;
    const bool started = try_start_thread(first_stage, [&] {
      try {
        for (std::size_t w = 0; w < windows.size(); ++w) {
          layer_window(w);
          const std::lock_guard<std::mutex> lock(mutex);
          windows_layered = w + 1;
          layered.notify_one();
          if (stop) return;
        }
      } catch (...) {
        const std::lock_guard<std::mutex> lock(mutex);
        first_failure = std::current_exception();
        layered.notify_one();
      }
    });
    if (!started) in_order();  // no thread to be had: both stages here
    try {
      for (std::size_t w = 0; first_stage.joinable() && w < windows.size(); ++w) {
        {
          std::unique_lock<std::mutex> lock(mutex);
          layered.wait(lock, [&] { return windows_layered > w || first_failure; });
          if (first_failure) break;
        }
        reorder_window(w);
      }
    } catch (...) {
      second_failure = std::current_exception();
      const std::lock_guard<std::mutex> lock(mutex);
      stop = true;
    }
    if (first_stage.joinable()) first_stage.join();
    if (first_failure) std::rethrow_exception(first_failure);
    if (second_failure) std::rethrow_exception(second_failure);
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
