// The chunks of vertex splits (CHNK, pm-format.md §5.5, §5.6, §5.10, §5.11) and the index
// the writer makes with them (INDX), written and read side by side. A split names vl and vr
// by their places in u's ring of faces, and its moved faces are those between them
// (split_fans.h; Hoppe 1998, "Efficient implementation of progressive meshes", §4); u is the
// gap from the previous u of its layer of independent splits (Pajarola and Rossignac 2000,
// "Compressed progressive meshes", §3); the new vertex's position is the residual from the
// mean of its neighbours (positions.h; Taubin, Guéziec, Horn and Lazarus 1998, §5); then its
// error, colours and corners' ids (corner_codes.h in 2.0 and 2.1, wedge_codes.h since 2.2).
// Since 2.1, u, vl, vr and the positions are range-coded (range_coder.h). The reader checks
// every code before it uses it, and replays each split on the fans as it goes.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "byte_io.h"
#include "pm/pm_codec.h"
#include "range_coder.h"
#include "split_fans.h"
#include "v2/format.h"
#include "v2/positions.h"
#include "v2/reader.h"
#include "v2/writer.h"
#include "wedge_codes.h"

namespace pm::detail::v2 {
namespace {

// A ring code (vl's or vr's, 0 .. n + 1 for a fan of n faces): a binary tree of
// bit_length(n + 1) bits with the models of its ring size, or exp-Golomb for rings of 63
// faces or more.
void put_ring_code(RangeEncoder& rc, TreeModels* trees, EgModels& large, std::size_t n,
                   uint32_t code) {
  const uint32_t bits = bit_length(uint64_t{n} + 1);
  if (bits <= kTreeBits) {
    put_tree(rc, trees[std::min<std::size_t>(n, kRingContexts - 1)], static_cast<int>(bits), code);
  } else {
    put_eg(rc, large, code);
  }
}

bool get_ring_code(RangeDecoder& rc, TreeModels* trees, EgModels& large, std::size_t n,
                   uint32_t& code) {
  const uint32_t bits = bit_length(uint64_t{n} + 1);
  if (bits <= kTreeBits) {
    code = get_tree(rc, trees[std::min<std::size_t>(n, kRingContexts - 1)], static_cast<int>(bits));
    return true;
  }
  uint64_t value = 0;
  if (!get_eg(rc, large, value) || value > 0xFFFFFFFFu) return false;
  code = static_cast<uint32_t>(value);
  return true;
}

// 2.4 (§5.11): the split's moved faces with u's place in each, for the wedge coders.
void arc_faces(const SplitFans& fans, uint32_t u, const std::vector<uint32_t>& arc,
               std::vector<WedgeCoder::ArcFace>& out) {
  out.clear();
  for (uint32_t f : arc) out.push_back({f, fans.face(f), fans.slot_of(f, u)});
}

}  // namespace

// The chunks and their index (§5.5, §5.6), replaying the splits on the fans.
void Writer::chunks(const std::function<void(std::string&&)>& emit, std::string& index) {
  SplitFans fans;
  fans.reset(h.split_vertices(), uint64_t{h.base_face_count} + h.split_face_count);
  for (std::size_t f = 0; f < pm.base_face_count(); ++f) {
    fans.add_face(pm.base_faces[3 * f], pm.base_faces[3 * f + 1], pm.base_faces[3 * f + 2]);
  }
  SplitFans::Fan fan;
  const bool ranged = h.minor >= 1, wedged = h.minor >= 2;
  if (wedged) start_wedges();
  SplitFans::Prefetch prefetch(fans, &positions.units);
  if (colors.components != 0) prefetch.also_values(&colors.units, colors.components);
  for (int kind = 0; kind < 2; ++kind) {
    if (!wedged || !has_ids(kind)) continue;
    prefetch.also_rows(&wedges[kind].level_ids(), &wedges[kind].all_units(),
                       wedges[kind].components());
  }
  for (std::size_t k = 0; k < SplitFans::Prefetch::kAhead; ++k)
    prefetch.step(k < pm.splits.size() ? pm.splits[k].u : SplitFans::kNone);
  std::vector<uint32_t> arc, record, sorted_arc, sorted_record, neighbours;
  std::vector<WedgeCoder::ArcFace> arc_sides;
  std::vector<int64_t> offsets;  // with_fan_offsets' scratch
  std::vector<uint32_t> predicted(3), color_predicted(colors.components);
  ByteWriter index_out(index);
  float previous_error = h.max_error;
  uint32_t next_face = static_cast<uint32_t>(pm.base_face_count());
  std::size_t i = 0;
  std::vector<uint64_t> position_codes, color_codes;
  // The moved corners' ids, when the mesh has any (2.2: their faces, for the wedges).
  const bool moved_ids = has_ids(0) || has_ids(1);
  // The models carry over from chunk to chunk (§5.10): chunks are decoded in order anyway.
  auto models = std::make_unique<ChunkModels>();
  uint32_t wedge_units[3];
  // The wedge ids of the split kValuesAhead further on are known now: their values (and the
  // wedge coders' places of them), as good as random in the split order, are asked for then
  // and read without waiting (write_pm of the 950K-face textured mesh: 1157 -> 1020 ms).
  constexpr std::size_t kValuesAhead = 16;
  std::size_t asked = 0;  // the splits whose ids were asked for
  uint32_t asked_face = next_face;
  const auto ask_values = [&](std::size_t until) {
    for (until = std::min(until, pm.splits.size()); asked < until; ++asked) {
      const VertexSplit& split = pm.splits[asked];
      const uint32_t new_faces = (split.vl != kNoVertex) + (split.vr != kNoVertex);
      for (int kind = 0; kind < 2; ++kind) {
        if (!has_ids(kind)) continue;
        for (const uint32_t vertex : {split.u, split.vl, split.vr})
          if (vertex != kNoVertex) wedges[kind].prefetch_vertex(vertex);
        const std::vector<uint32_t>& moved = mesh_moved_ids(pm, kind);
        const std::vector<uint32_t>& faces = mesh_face_ids(pm, kind);
        for (std::size_t k = 0; k < split.moved_count; ++k)
          prefetch_units(kind, moved[split.moved_begin + k]);
        for (std::size_t c = 3 * std::size_t{asked_face};
             c < 3 * (std::size_t{asked_face} + new_faces) && c < faces.size(); ++c)
          prefetch_units(kind, faces[c]);
      }
      asked_face += new_faces;
    }
  };
  for (uint32_t size : plan_chunks(h.split_count, options.chunk_splits)) {
    std::string streams[kChunkStreams];
    RangeEncoder u_rc(streams[kStreamU]), vl_rc(streams[kStreamVl]), vr_rc(streams[kStreamVr]),
        position_rc(streams[kStreamPositions]), uv_rc(streams[kStreamUvCodes]),
        normal_rc(streams[kStreamNormalCodes]);
    RangeEncoder* wedge_rc[2] = {&uv_rc, &normal_rc};
    int64_t previous_u = -1;
    position_codes.clear();
    color_codes.clear();
    ChunkEntry entry;
    entry.splits = size;
    ByteWriter u_out(streams[kStreamU]), vl_out(streams[kStreamVl]), vr_out(streams[kStreamVr]),
        explicit_out(streams[kStreamExplicit]), material_out(streams[kStreamMaterials]),
        uv_out(streams[kStreamUvCodes]), normal_out(streams[kStreamNormalCodes]);
    previous_error = error_before(i);  // the index's error before this chunk
    for (const std::size_t end = i + size; i < end; ++i) {
      const VertexSplit& split = pm.splits[i];
      const auto v = static_cast<uint32_t>(pm.base_vertex_count + i);
      if (ranged) {
        // u as the gap from the previous u of its layer (§5.10); a new layer starts
        // wherever u does not grow.
        const bool first = i + size == end;
        const bool restart = !first && int64_t{split.u} <= previous_u;
        if (!first) u_rc.bit(models->restart, restart ? 1 : 0);
        if (first || restart) previous_u = -1;
        put_eg(u_rc, models->u_gap[previous_u < 0 ? 0 : 1],
               static_cast<uint64_t>(split.u - previous_u - 1));
        previous_u = split.u;
      } else {
        u_out.put_varint(v - 1 - split.u);
      }
      const float error = error_before(i);
      const int64_t error_step = int64_t{ordered_from_float(previous_error)} -
                                 int64_t{ordered_from_float(error)};
      put_varint64(streams[kStreamErrors], zigzag(error_step));
      previous_error = error;
      record.assign(pm.moved_faces.begin() + split.moved_begin,
                    pm.moved_faces.begin() + split.moved_begin + split.moved_count);
      const std::size_t ahead = i + SplitFans::Prefetch::kAhead;
      prefetch.step(ahead < pm.splits.size() ? pm.splits[ahead].u : SplitFans::kNone);
      if (wedged && moved_ids) ask_values(i + kValuesAhead);
      // One-ring coding when the moved faces are the arc from vl to vr around u.
      bool coded = false;
      std::size_t place_l = 0, place_r = 0;
      const bool has_fan = fans.fan(split.u, fan);
      if (has_fan) {
        const std::size_t places = fan.closed ? fan.faces.size() : fan.ring.size();
        const auto place = [&](uint32_t vertex, std::size_t none) {
          if (vertex == kNoVertex) return fan.closed ? places : none;
          const auto it = std::find(fan.ring.begin(), fan.ring.begin() + places, vertex);
          return static_cast<std::size_t>(it - fan.ring.begin());
        };
        place_l = place(split.vl, 0);
        place_r = place(split.vr, fan.faces.size());
        if (place_l < places && place_r <= places && SplitFans::arc(fan, place_l, place_r, arc)) {
          sorted_arc = arc;
          std::sort(sorted_arc.begin(), sorted_arc.end());
          sorted_record = record;
          std::sort(sorted_record.begin(), sorted_record.end());
          coded = sorted_arc == sorted_record;
        }
      }
      neighbours.assign(1, split.u);
      if (coded) {
        uint32_t vl_code = split.vl == kNoVertex ? 0 : static_cast<uint32_t>(place_l) + 1;
        const uint32_t vr_code =
            split.vr == kNoVertex ? 0 : static_cast<uint32_t>(arc.size()) + 1;
        if (ranged) {
          // 2.1: a closed fan's places counted from its lopsided place (§5.10).
          if (fan.closed) {
            const std::size_t n = fan.faces.size();
            vl_code = static_cast<uint32_t>(
                          (place_l + n - lopsided_place(positions, split.u, fan, offsets)) % n) +
                      1;
          }
          put_ring_code(vl_rc, models->vl, models->vl_large, fan.faces.size(), vl_code);
          put_ring_code(vr_rc, models->vr, models->vr_large, fan.faces.size(), vr_code);
        } else {
          vl_out.put_varint(vl_code);
          vr_out.put_varint(vr_code);
        }
        const std::size_t n = fan.faces.size();
        for (std::size_t k = 0; k <= arc.size(); ++k) {
          neighbours.push_back(fan.ring[fan.closed ? (place_l + k) % n : place_l + k]);
        }
      } else {
        if (!ranged) {
          vl_out.put_varint(0);
          vr_out.put_varint(0);
        } else if (has_fan) {  // a fan, but not an arc of it: both codes 0
          put_ring_code(vl_rc, models->vl, models->vl_large, fan.faces.size(), 0);
          put_ring_code(vr_rc, models->vr, models->vr_large, fan.faces.size(), 0);
        }
        explicit_out.put_varint(split.vl == kNoVertex ? 0 : split.vl + 1);
        explicit_out.put_varint(split.vr == kNoVertex ? 0 : split.vr + 1);
        explicit_out.put_varint(split.moved_count);
        for (uint32_t f : record) explicit_out.put_varint(f);
        arc = record;
      }
      // The new vertex's position and colour, against the mean of its neighbours.
      positions.predict(neighbours.data(), neighbours.size(), predicted.data());
      // On a grid (2.1) or of significant decimals (2.4), the coordinate along u's normal
      // last, predicted from the others.
      NormalFrame frame;
      const bool framed = ranged && positions.has_frames() && has_fan &&
                          normal_frame(positions, split.u, fan, offsets, frame);
      int64_t r[3], d[3];
      const uint32_t* at_u = &positions.units[3 * std::size_t{split.u}];
      const uint32_t* at_v = &positions.units[3 * std::size_t{v}];
      for (int c = 0; c < 3; ++c) {
        r[c] = int64_t{at_v[c]} - predicted[c];
        d[c] = int64_t{predicted[c]} - at_u[c];
      }
      for (int k = 0; k < 3; ++k) {
        const int c = frame.order[k];
        const bool along_normal = framed && k == 2;
        int64_t residual = r[c];
        if (along_normal && positions.grid == nullptr) {  // 2.4: significant decimals
          residual = int64_t{at_v[c]} - normal_prediction_of_values(*positions.significant, frame,
                                                                    at_u, predicted.data(), at_v);
        } else if (along_normal) {
          residual -= normal_offset(frame, d, r, position_grid.bits);
        }
        if (ranged) {
          // |residual| and its sign, with the models of its neighbours' spread (§5.10).
          const uint32_t context =
              positions.spread_context(neighbours.data(), neighbours.size(), predicted[c], c);
          put_eg(position_rc, models->position[along_normal][context],
                 static_cast<uint64_t>(residual < 0 ? -residual : residual));
          const int side = d[c] < 0 ? 0 : d[c] == 0 ? 1 : 2;
          if (residual != 0)
            position_rc.bit(models->sign[along_normal][context][side], residual < 0 ? 1 : 0);
        } else {
          position_codes.push_back(zigzag(residual));
        }
      }
      if (colors.components != 0) {
        colors.predict(neighbours.data(), neighbours.size(), color_predicted.data());
        for (std::size_t c = 0; c < colors.components; ++c) {
          color_codes.push_back(zigzag(int64_t{colors.units[colors.components * v + c]} - color_predicted[c]));
        }
      }
      // Attributes: the moved corners in the order stored (the arc's), then fl and fr.
      if (wedged && moved_ids) arc_faces(fans, split.u, arc, arc_sides);
      for (std::size_t m = 0; moved_ids && m < arc.size(); ++m) {
        const uint32_t f = arc[m];
        const std::size_t k = split.moved_begin +
                              (std::find(record.begin(), record.end(), f) - record.begin());
        if (wedged) {  // 2.2 (§5.11)
          const int slot = arc_sides[m].slot;
          const WedgeCoder::Corner at{kRoleMoved, v, v, arc_sides.data(), arc_sides.size(), m};
          for (int kind = 0; kind < 2; ++kind) {
            if (!has_ids(kind)) continue;
            const uint32_t id = mesh_moved_ids(pm, kind)[k];
            if (id != kNoAttribute) units_of(kind, id, wedge_units);
            wedges[kind].encode(*wedge_rc[kind], positions.units, at, id, wedge_units);
            wedges[kind].move(f, slot, id);
          }
          continue;
        }
        if (pm.has_uvs()) uv_out.put_varint(uv_codes.encode(v, pm.moved_uvs[k]));
        if (pm.has_normals()) normal_out.put_varint(normal_codes.encode(v, pm.moved_normals[k]));
      }
      for (int side = 0; side < 2; ++side) {
        const uint32_t other = side == 0 ? split.vl : split.vr;
        if (other == kNoVertex) continue;
        const uint32_t corners[3] = {side == 0 ? v : split.u, side == 0 ? split.u : v, other};
        for (int c = 0; c < 3; ++c) {
          const std::size_t slot = 3 * std::size_t{next_face} + c;
          if (!wedged) {
            put_corner(uv_out, normal_out, corners[c], slot);
            continue;
          }
          const WedgeCoder::Corner at{new_face_role(c, corners[c], v), corners[c]};
          for (int kind = 0; kind < 2; ++kind) {
            if (!has_ids(kind)) continue;
            const uint32_t id = mesh_face_ids(pm, kind)[slot];
            if (id != kNoAttribute) units_of(kind, id, wedge_units);
            wedges[kind].encode(*wedge_rc[kind], positions.units, at, id, wedge_units);
          }
        }
        if (pm.has_materials()) put_optional_id(material_out, pm.face_materials[next_face]);
        ++next_face;
        ++entry.new_faces;
      }
      entry.moved_faces += split.moved_count;
      fans.split(split.u, v, split.vl, split.vr, arc.data(), arc.size(), coded ? &fan : nullptr,
                 place_l);
    }
    entry.error_after = error_before(i);
    index_out.put_varint(entry.splits);
    index_out.put_varint(entry.new_faces);
    index_out.put_varint(entry.moved_faces);
    index_out.put_f32(entry.error_after);
    if (wedged) {
      for (int kind = 0; kind < 2; ++kind) {
        if (has_ids(kind)) wedge_rc[kind]->finish();
      }
    }
    if (ranged) {
      for (RangeEncoder* rc : {&u_rc, &vl_rc, &vr_rc, &position_rc}) rc->finish();
    } else {
      put_planes(streams[kStreamPositions], position_codes);
    }
    put_planes(streams[kStreamColors], color_codes);
    std::string raw;
    for (const std::string& stream : streams) put_varint64(raw, stream.size());
    for (const std::string& stream : streams) raw += stream;
    emit(std::move(raw));
  }
}

}  // namespace pm::detail::v2

namespace pm {

bool PmStreamReader::State::decode_chunk(ByteReader& in) {
  const ChunkEntry& entry = index[chunks_decoded];
  const std::string where = in.where();
  // The streams' sizes, then the streams (§5.5).
  uint64_t sizes[kChunkStreams];
  for (uint64_t& size : sizes) {
    if (!read_varint64(in, size)) return false;
  }
  std::vector<ByteReader> streams;
  streams.reserve(kChunkStreams);
  std::string_view stream_bytes[kChunkStreams];
  for (int k = 0; k < kChunkStreams; ++k) {
    std::string_view& bytes = stream_bytes[k];
    if (!in.read_bytes(sizes[k], bytes)) return false;
    streams.emplace_back(bytes, where + " (" + kStreamNames[k] + ")", ErrorCode::kCorruptStream);
  }
  const auto failed = [&](ByteReader& stream) { return in.fail(stream.status().code(), stream.status().message()); };
  const auto bad = [&](uint32_t v, const std::string& what) {
    return in.fail(ErrorCode::kCorruptStream,
                   where + ": split " + std::to_string(v - h.base_vertex_count) + " " + what);
  };
  ByteReader &u_in = streams[kStreamU], &vl_in = streams[kStreamVl], &vr_in = streams[kStreamVr],
             &explicit_in = streams[kStreamExplicit], &error_in = streams[kStreamErrors],
             &position_in = streams[kStreamPositions], &color_in = streams[kStreamColors],
             &material_in = streams[kStreamMaterials], &uv_in = streams[kStreamUvCodes],
             &normal_in = streams[kStreamNormalCodes];
  float previous_error = chunks_decoded == 0 ? h.max_error : index[chunks_decoded - 1].error_after;
  SplitFans::Fan fan;
  std::vector<uint32_t> arc, neighbours;
  std::vector<WedgeCoder::ArcFace> arc_sides;
  std::vector<int64_t> offsets;  // with_fan_offsets' scratch
  uint32_t predicted[3];
  std::vector<uint32_t> color_predicted(h.color_components);
  uint32_t new_faces = 0, moved_total = 0;
  std::vector<uint64_t> position_codes, color_codes;
  // 2.1 (§5.10): u, vl, vr and the positions are range codes, with fresh models per chunk.
  const bool ranged = h.minor >= 1;
  std::optional<RangeDecoder> u_rc, vl_rc, vr_rc, position_rc;
  // 2.2 (§5.11): the corners' ids and new values, a range code per kind.
  const bool wedged = h.minor >= 2;
  std::optional<RangeDecoder> wedge_rc[2];
  if (wedged) {
    if (!wedges_ready) {  // no TABL: no table entries
      reset_wedges();
      if (!start_wedges(in)) return false;
    }
    if (h.uv_ids()) wedge_rc[0].emplace(stream_bytes[kStreamUvCodes]);
    if (h.normal_ids()) wedge_rc[1].emplace(stream_bytes[kStreamNormalCodes]);
  }
  std::string wedge_problem;
  const auto wedge_corner = [&](int kind, const WedgeCoder::Corner& at, uint32_t& id) {
    if (!wedges[kind].decode(*wedge_rc[kind], positions.units, at, id, wedge_problem) ||
        !wedge_rc[kind]->ok()) {
      return in.fail(ErrorCode::kCorruptStream,
                     where + " (" + kStreamNames[corner_code_stream(kind)] +
                         "): a corner of vertex " + std::to_string(at.vertex) + " " +
                         (wedge_problem.empty() ? "is cut short" : wedge_problem));
    }
    if (id != kNoAttribute) {
      std::vector<float>& values = mesh_table(pm, kind);
      const std::size_t components = kind_components(kind);
      const uint32_t* units = wedges[kind].units(id);
      const Grid* table_grid = h.table_bits(kind) != 0 ? &grid(kind) : nullptr;
      for (std::size_t c = 0; c < components; ++c) {  // 2.3's numbers too (§5.4)
        if (!float_of_unit(table_grid, in_use(table_significant[kind]), units[c], c,
                           values[components * std::size_t{id} + c])) {
          return in.fail(ErrorCode::kCorruptStream, where + ": a corner of vertex " +
                                                        std::to_string(at.vertex) +
                                                        " has a table value that is no decimal's");
        }
      }
    }
    return true;
  };
  if (ranged) {
    if (!models) models = std::make_unique<ChunkModels>();  // kept from chunk to chunk
    u_rc.emplace(stream_bytes[kStreamU]);
    vl_rc.emplace(stream_bytes[kStreamVl]);
    vr_rc.emplace(stream_bytes[kStreamVr]);
    position_rc.emplace(stream_bytes[kStreamPositions]);
  } else if (!read_planes(position_in, 3 * std::size_t{entry.splits}, position_codes)) {
    return failed(position_in);
  }
  int64_t previous_u = -1;
  const auto range_failed = [&](const char* stream) {
    return in.fail(ErrorCode::kCorruptStream,
                   where + " (" + stream + "): the range code is corrupt or ends early");
  };
  if (!read_planes(color_in, std::size_t{h.color_components} * entry.splits, color_codes)) {
    return failed(color_in);
  }
  std::size_t next_position = 0, next_color = 0;
  // 2.1: u has a range code of its own, so the chunk's u are decoded first, and their fans
  // fetched a few splits ahead of their turn (SplitFans::Prefetch).
  if (ranged) {
    chunk_u.resize(entry.splits);
    for (uint32_t j = 0; j < entry.splits; ++j) {
      const auto v = static_cast<uint32_t>(h.base_vertex_count + pm.splits.size() + j);
      if (j > 0 && u_rc->bit(models->restart) != 0) previous_u = -1;
      if (j == 0) previous_u = -1;
      uint64_t gap = 0;
      if (!get_eg(*u_rc, models->u_gap[previous_u < 0 ? 0 : 1], gap) || !u_rc->ok())
        return range_failed("u");
      if (gap >= uint64_t{v} || previous_u + 1 + static_cast<int64_t>(gap) >= int64_t{v}) {
        return bad(v, "names u beyond the vertices before it");
      }
      chunk_u[j] = static_cast<uint32_t>(previous_u + 1 + static_cast<int64_t>(gap));
      previous_u = chunk_u[j];
    }
  }
  // The moved corners' ids, when the stream has any (2.2: their faces, for the wedges).
  const bool moved_ids = wedged ? wedge_rc[0] || wedge_rc[1] : uv_codes || normal_codes;
  SplitFans::Prefetch prefetch(fans, &positions.units);
  if (h.color_components != 0) prefetch.also_values(&colors.units, h.color_components);
  for (int kind = 0; kind < 2; ++kind) {
    if (!wedge_rc[kind]) continue;
    prefetch.also_rows(&wedges[kind].level_ids(), &wedges[kind].all_units(),
                       wedges[kind].components());
  }
  constexpr std::size_t kAhead = SplitFans::Prefetch::kAhead;
  for (std::size_t k = 0; ranged && k < kAhead; ++k)
    prefetch.step(k < entry.splits ? chunk_u[k] : SplitFans::kNone);
  for (uint32_t j = 0; j < entry.splits; ++j) {
    const auto v = static_cast<uint32_t>(h.base_vertex_count + pm.splits.size());
    VertexSplit split;
    uint32_t u_offset, vl_code = 0, vr_code = 0;
    if (ranged) {
      split.u = chunk_u[j];
      prefetch.step(j + kAhead < entry.splits ? chunk_u[j + kAhead] : SplitFans::kNone);
    } else {
      if (!u_in.read_varint(u_offset)) return failed(u_in);
      if (u_offset >= v)
        return bad(
            v, "names u " + std::to_string(u_offset) + " before itself, of " + std::to_string(v));
      split.u = v - 1 - u_offset;
    }
    uint64_t error_code;
    if (!read_varint64(error_in, error_code)) return failed(error_in);
    int64_t error_step = 0;
    if (!residual_of(error_code, error_step)) return bad(v, "has an impossible error");
    const int64_t error_bits = int64_t{ordered_from_float(previous_error)} - error_step;
    if (error_bits < 0 || error_bits > 0xFFFFFFFFll) return bad(v, "has an impossible error");
    split.error = float_from_ordered(static_cast<uint32_t>(error_bits));
    if (!std::isfinite(split.error) || split.error < 0 || split.error > previous_error ||
        (j == 0 && ordered_from_float(split.error) != ordered_from_float(previous_error))) {
      return bad(v, "has an error that is negative, not finite, larger than the one before, or "
                    "not the index's");
    }
    previous_error = split.error;
    bool has_fan = false;
    if (ranged) {
      // The ring codes exist only when u has a fan (§5.10); without one the split is explicit.
      has_fan = fans.fan(split.u, fan);
      if (has_fan) {
        if (!get_ring_code(*vl_rc, models->vl, models->vl_large, fan.faces.size(), vl_code) ||
            !vl_rc->ok()) {
          return range_failed("vl");
        }
        if (!get_ring_code(*vr_rc, models->vr, models->vr_large, fan.faces.size(), vr_code) ||
            !vr_rc->ok()) {
          return range_failed("vr");
        }
      }
    } else {
      if (!vl_in.read_varint(vl_code)) return failed(vl_in);
      if (!vr_in.read_varint(vr_code)) return failed(vr_in);
    }
    neighbours.assign(1, split.u);
    // Both codes 0: an explicit split; otherwise the moved faces are the arc of `fan` from
    // place arc_first.
    const bool explicit_split = vl_code == 0 && vr_code == 0;
    std::size_t arc_first = 0;
    if (explicit_split) {
      // An explicit split: vl, vr and the moved faces as ids (§5.5).
      uint32_t codes[3];
      for (uint32_t& code : codes) {
        if (!explicit_in.read_varint(code)) return failed(explicit_in);
      }
      split.vl = codes[0] == 0 ? kNoVertex : codes[0] - 1;
      split.vr = codes[1] == 0 ? kNoVertex : codes[1] - 1;
      if ((split.vl != kNoVertex && split.vl >= v) || (split.vr != kNoVertex && split.vr >= v) ||
          (split.vl == kNoVertex && split.vr == kNoVertex) || split.vl == split.u ||
          split.vr == split.u || (split.vl == split.vr)) {
        return bad(v, "has impossible vl and vr");
      }
      if (codes[2] > fans.face_count() || codes[2] > h.moved_face_count) return bad(v, "moves too many faces");
      arc.clear();
      for (uint32_t k = 0; k < codes[2]; ++k) {
        uint32_t f;
        if (!explicit_in.read_varint(f)) return failed(explicit_in);
        if (!fans.holds_once(f, split.u) || std::find(arc.begin(), arc.end(), f) != arc.end()) {
          return bad(v, "moves face " + std::to_string(f) + ", which does not hold u once or is moved twice");
        }
        arc.push_back(f);
      }
    } else {
      if (!has_fan && !fans.fan(split.u, fan))
        return bad(v, "names places around u, whose faces are not a fan");
      const std::size_t n = fan.faces.size();
      std::size_t i = 0, end = n;
      if (vl_code != 0) {
        i = vl_code - 1;
        if (i >= (fan.closed ? n : n + 1)) return bad(v, "names place " + std::to_string(i) + " of u's ring for vl");
        if (ranged && fan.closed) i = (i + lopsided_place(positions, split.u, fan, offsets)) % n;  // §5.10
      } else if (fan.closed) {
        return bad(v, "has no vl on a closed fan");
      }
      if (vr_code != 0) {
        const uint64_t length = vr_code - 1;
        if (length > n) return bad(v, "moves more faces than u has");
        end = fan.closed ? (i + length) % n : i + length;
        if (!fan.closed && end > n) return bad(v, "moves faces beyond the end of u's fan");
      } else if (fan.closed) {
        return bad(v, "has no vr on a closed fan");
      }
      if (!SplitFans::arc(fan, i, end, arc)) return bad(v, "names an impossible arc of u's fan");
      arc_first = i;
      split.vl = vl_code == 0 ? kNoVertex : fan.ring[i];
      split.vr = vr_code == 0 ? kNoVertex : fan.ring[end];
      for (std::size_t k = 0; k <= arc.size(); ++k) neighbours.push_back(fan.ring[fan.closed ? (i + k) % n : i + k]);
    }
    if (moved_total + arc.size() > entry.moved_faces) return bad(v, "moves more faces than the index says");
    split.moved_begin = static_cast<uint32_t>(pm.moved_faces.size());
    split.moved_count = static_cast<uint32_t>(arc.size());
    moved_total += split.moved_count;
    pm.moved_faces.insert(pm.moved_faces.end(), arc.begin(), arc.end());
    // The position and colour: the neighbours' mean plus the residual.
    positions.predict(neighbours.data(), neighbours.size(), predicted);
    NormalFrame frame;
    const bool framed =
        ranged && positions.has_frames() && has_fan && normal_frame(positions, split.u, fan, offsets, frame);
    int64_t r[3] = {0, 0, 0}, d[3];
    uint32_t units[3] = {0, 0, 0};  // v's, as decoded so far
    for (int c = 0; c < 3; ++c)
      d[c] = int64_t{predicted[c]} - positions.units[3 * std::size_t{split.u} + c];
    for (int k = 0; k < 3; ++k) {
      const int c = frame.order[k];
      const bool along_normal = framed && k == 2;
      int64_t residual = 0;
      if (ranged) {
        const uint32_t context =
            positions.spread_context(neighbours.data(), neighbours.size(), predicted[c], c);
        uint64_t magnitude = 0;
        if (!get_eg(*position_rc, models->position[along_normal][context], magnitude))
          return range_failed("positions");
        if (magnitude > 0xFFFFFFFFu) return bad(v, "has a position beyond the grid");
        residual = static_cast<int64_t>(magnitude);
        const int side = d[c] < 0 ? 0 : d[c] == 0 ? 1 : 2;
        if (magnitude != 0 && position_rc->bit(models->sign[along_normal][context][side]) != 0)
          residual = -residual;
        if (!position_rc->ok()) return range_failed("positions");
      } else if (!residual_of(position_codes[next_position++], residual)) {
        return bad(v, "has a position beyond the grid");
      }
      int64_t unit = int64_t{predicted[c]} + residual;
      if (along_normal && positions.grid == nullptr) {  // 2.4: significant decimals
        unit = int64_t{normal_prediction_of_values(*positions.significant, frame,
                                                   &positions.units[3 * std::size_t{split.u}],
                                                   predicted, units)} + residual;
      } else if (along_normal) {
        unit += normal_offset(frame, d, r, position_grid.bits);  // r of the other two: checked
      }
      const int64_t top = h.position_bits != 0 ? (int64_t{1} << h.position_bits) - 1 : 0xFFFFFFFFll;
      if (unit < 0 || unit > top) return bad(v, "has a position beyond the grid");
      r[c] = residual;
      units[c] = static_cast<uint32_t>(unit);
    }
    for (int c = 0; c < 3; ++c) {
      positions.units.push_back(units[c]);
      float x = 0;
      if (!positions.to_float(units[c], c, x)) {
        return bad(v, "has a position that is no decimal's (§5.3)");
      }
      pm.positions.push_back(x);
    }
    if (h.color_components != 0) {
      colors.predict(neighbours.data(), neighbours.size(), color_predicted.data());
      for (std::size_t c = 0; c < h.color_components; ++c) {
        int64_t residual = 0;
        if (!residual_of(color_codes[next_color++], residual)) return bad(v, "has an impossible colour");
        const int64_t unit = int64_t{color_predicted[c]} + residual;
        if (unit < 0 || unit > 0xFFFFFFFFll) return bad(v, "has an impossible colour");
        colors.units.push_back(static_cast<uint32_t>(unit));
        pm.colors.push_back(float_from_ordered(static_cast<uint32_t>(unit)));
      }
    }
    // Attributes: the moved corners, then the new faces' corners and materials.
    if (wedged && moved_ids) arc_faces(fans, split.u, arc, arc_sides);
    for (std::size_t k = 0; moved_ids && k < arc.size(); ++k) {
      uint32_t id;
      if (wedged) {  // 2.2 (§5.11)
        const uint32_t f = arc[k];
        const int slot = arc_sides[k].slot;
        const WedgeCoder::Corner at{kRoleMoved, v, v, arc_sides.data(), arc_sides.size(), k};
        for (int kind = 0; kind < 2; ++kind) {
          if (!wedge_rc[kind]) continue;
          if (!wedge_corner(kind, at, id)) return false;
          wedges[kind].move(f, slot, id);
          mesh_moved_ids(pm, kind).push_back(id);
        }
        continue;
      }
      if (uv_codes) {
        if (!read_corner(uv_in, 0, v, id)) return failed(uv_in);
        pm.moved_uvs.push_back(id);
      }
      if (normal_codes) {
        if (!read_corner(normal_in, 1, v, id)) return failed(normal_in);
        pm.moved_normals.push_back(id);
      }
    }
    for (int side = 0; side < 2; ++side) {
      const uint32_t other = side == 0 ? split.vl : split.vr;
      if (other == kNoVertex) continue;
      const uint32_t corners[3] = {side == 0 ? v : split.u, side == 0 ? split.u : v, other};
      for (int c = 0; c < 3 && wedged; ++c) {  // 2.2 (§5.11)
        const WedgeCoder::Corner at{new_face_role(c, corners[c], v), corners[c]};
        for (int kind = 0; kind < 2; ++kind) {
          if (!wedge_rc[kind]) continue;
          uint32_t id;
          if (!wedge_corner(kind, at, id)) return false;
          mesh_face_ids(pm, kind).push_back(id);
        }
      }
      for (uint32_t corner : corners) {
        if (wedged) break;
        uint32_t id;
        if (uv_codes) {
          if (!read_corner(uv_in, 0, corner, id)) return failed(uv_in);
          pm.face_uvs.push_back(id);
        }
        if (normal_codes) {
          if (!read_corner(normal_in, 1, corner, id)) return failed(normal_in);
          pm.face_normals.push_back(id);
        }
      }
      if (h.material_ids()) {
        uint32_t id;
        if (!read_optional_id(material_in, h.material_count, "material", id)) return failed(material_in);
        pm.face_materials.push_back(id);
      }
      ++new_faces;
    }
    if (new_faces > entry.new_faces) return bad(v, "adds more faces than the index says");
    fans.split(split.u, v, split.vl, split.vr, arc.data(), arc.size(),
               explicit_split ? nullptr : &fan, arc_first);
    pm.splits.push_back(split);
  }
  if (new_faces != entry.new_faces || moved_total != entry.moved_faces) {
    return in.fail(ErrorCode::kCorruptStream, where + ": its splits add " + std::to_string(new_faces) +
                                                  " faces and move " + std::to_string(moved_total) +
                                                  ", the index says " + std::to_string(entry.new_faces) +
                                                  " and " + std::to_string(entry.moved_faces));
  }
  if (ordered_from_float(previous_error) < ordered_from_float(entry.error_after)) {
    return in.fail(ErrorCode::kCorruptStream, where + ": the index's error after it is larger than its last");
  }
  if (ranged) {
    for (auto* rc : {&u_rc, &vl_rc, &vr_rc, &position_rc}) {
      if (!(*rc)->ok() || !(*rc)->at_end()) {
        return in.fail(
            ErrorCode::kCorruptStream,
            where + ": a range-coded stream is corrupt, ends early or has bytes left over");
      }
    }
    for (int k : {kStreamU, kStreamVl, kStreamVr, kStreamPositions})
      streams[k].skip(streams[k].remaining());
  }
  for (int kind = 0; kind < 2; ++kind) {
    if (!wedge_rc[kind]) continue;
    if (!wedge_rc[kind]->ok() || !wedge_rc[kind]->at_end()) {
      return in.fail(ErrorCode::kCorruptStream,
                     where + ": a corner attribute code is corrupt, ends early or has bytes left over");
    }
    ByteReader& stream = streams[corner_code_stream(kind)];
    stream.skip(stream.remaining());
  }
  for (ByteReader& stream : streams) {
    if (!stream.at_end()) {
      return in.fail(ErrorCode::kCorruptStream, stream.where() + ": " +
                                                    std::to_string(stream.remaining()) + " bytes left over");
    }
  }
  decoded_faces += new_faces;
  ++chunks_decoded;
  return true;
}

}  // namespace pm
