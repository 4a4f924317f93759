// 2.2 (pm-format.md §5.11): the texture-coordinate and normal ids of the splits' corners,
// and the values of the ids they introduce, as range codes. A vertex's corners share few
// wedges (Hoppe 1996, §3: a wedge is the set of a vertex's corners with one attribute
// value), so each corner is coded as a choice among the wedges its vertex already has,
// most recent first, or a new one; with the table in the order in which the splits first
// use its entries (order_attribute_tables), a new one is the first id not yet known and
// costs almost nothing, and its value is coded where it is first used, predicted from the
// face it appears in: the affine map of that face's texture coordinates, applied to the new
// vertex's position (the face before the split maps positions to texture coordinates; v
// lies close to its plane). Isenburg and Snoeyink 2003, "Compressing texture coordinates
// with selective linear predictions" (CGI 2003), section "Compressing texture coordinates":
// choose the predictor by what the neighbourhood offers, and code each predictor's
// correctors with arithmetic contexts of their own (here t = 0 and 1). In 2.1 a new
// id cost its gap from the previous one and every value was stored raw in TABL: the
// texture coordinates of the spot mesh took 21 KB at 10 bits, against Draco's 4 KB.
// Integers only, so that every reader gets the same predictions. Internal to the codec.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "byte_io.h"
#include "range_coder.h"
#include "significant_decimals.h"
#include "pm/mesh.h"  // kNoAttribute

namespace pm::detail {

// The ids not known yet (known: listed in TABL or introduced by an earlier corner), with
// rank and select in O(log n) (a Fenwick tree of counts; Fenwick 1994).
class UnknownIds {
 public:
  void reset(uint32_t n) {
    n_ = n;
    unknown_ = n;
    tree_.assign(std::size_t{n} + 1, 0);
    for (uint32_t i = 1; i <= n; ++i) {
      tree_[i] += 1;
      const uint32_t parent = i + (i & (0u - i));
      if (parent <= n) tree_[parent] += tree_[i];
    }
    known_.assign(n, 0);
  }
  bool known(uint32_t id) const { return known_[id] != 0; }
  uint32_t unknown() const { return unknown_; }
  // Asks for what known(), rank() and mark_known() of `id` read first (id < n). Inlined
  // always, as every function that only prefetches must be: GCC 12 counts a prefetch as no
  // effect, so a call it leaves out of line (a partial inlining's clone) is found to do
  // nothing and deleted, prefetches and all.
  [[gnu::always_inline]] void prefetch(uint32_t id) const {
    __builtin_prefetch(&known_[id], 1);
    __builtin_prefetch(&tree_[id], 1);
  }
  void mark_known(uint32_t id) {
    known_[id] = 1;
    --unknown_;
    for (uint32_t i = id + 1; i <= n_; i += i & (0u - i)) --tree_[i];
  }
  // Unknown ids below `id`.
  uint32_t rank(uint32_t id) const {
    uint32_t sum = 0;
    for (uint32_t i = id; i > 0; i -= i & (0u - i)) sum += tree_[i];
    return sum;
  }
  // The unknown id of rank r (r < unknown()).
  uint32_t select(uint32_t r) const {
    uint32_t at = 0;
    uint32_t step = 1;
    while (step <= n_ / 2) step <<= 1;
    if (n_ == 0) return 0;
    for (; step != 0; step >>= 1) {
      const uint32_t next = at + step;
      if (next <= n_ && tree_[next] <= r) {
        at = next;
        r -= tree_[next];
      }
    }
    return at;  // ids are 0-based: the tree's index at + 1 is id at
  }
 private:
  uint32_t n_ = 0, unknown_ = 0;
  std::vector<uint32_t> tree_;
  std::vector<uint8_t> known_;
};

// Where a corner is (§5.11): a moved corner (the new vertex's, in a face that was u's), or a
// corner of a new face at the new vertex, at u, or at vl / vr.
enum WedgeRole { kRoleMoved, kRoleNewAtV, kRoleNewAtU, kRoleNewAtOther, kWedgeRoles };

// The role of corner c (0, 1, 2) of a new face whose vertex there is `corner`: fl is
// (v, u, vl), fr is (u, v, vr).
inline WedgeRole new_face_role(int c, uint32_t corner, uint32_t v) {
  return c == 2 ? kRoleNewAtOther : corner == v ? kRoleNewAtV : kRoleNewAtU;
}

constexpr uint32_t kWedgeValueContexts = 26;  // bit lengths 0..24 of the face's spread, then the rest
constexpr int kWedgeRecent = 3;               // wedges remembered per vertex

struct WedgeModels {
  BitModel none[kWedgeRoles];
  BitModel recent[kWedgeRoles][kWedgeRecent + 1][kWedgeRecent];  // [role][remembered][which]
  BitModel fresh[kWedgeRoles][kWedgeRecent + 1];
  EgModels rank, foreign;
  // [0]: predicted through a face's map; [1]: from one value
  EgModels value[2][kWedgeValueContexts];
  BitModel sign[2][kWedgeValueContexts];
};

// One kind's state (texture coordinates: 2 components; normals: 3), the same in the writer
// and the reader.
class WedgeCoder {
 public:
  // `top`: the largest unit (2^bits - 1 on a grid, 2^32 - 1 for float bits).
  void reset(std::size_t components, uint32_t count, uint64_t top, std::size_t vertices,
             std::size_t level_faces) {
    components_ = components;
    count_ = count;
    top_ = top;
    units_.assign(components * count, 0);
    ids_.reset(count);
    recent_.assign(kWedgeRecent * vertices, kNoAttribute);
    current_.clear();
    current_.reserve(3 * level_faces);
    previous_ = 0;
    by_values_ = false;
    position_numbers_ = value_numbers_ = nullptr;
    models_ = std::make_unique<WedgeModels>();
  }

  // An id whose value is known before the splits (TABL).
  void learn(uint32_t id, const uint32_t* units) {
    std::copy(units, units + components_, units_.begin() + components_ * std::size_t{id});
    ids_.mark_known(id);
  }
  bool known(uint32_t id) const { return ids_.known(id); }
  uint32_t unknown() const { return ids_.unknown(); }
  const uint32_t* units(uint32_t id) const { return units_.data() + components_ * std::size_t{id}; }
  // Asks for what encode() of `id` reads and writes at its place (id < count): a writer
  // knows its ids ahead, and ids are as good as random in the split order. Inlined always
  // (UnknownIds::prefetch says why).
  [[gnu::always_inline]] void prefetch(uint32_t id) const {
    if (id >= count_) return;
    __builtin_prefetch(units(id), 1);
    ids_.prefetch(id);
  }
  // Asks for the wedges `vertex` remembers (what encode() reads first for a new face's
  // corner there). Inlined always (UnknownIds::prefetch says why).
  [[gnu::always_inline]] void prefetch_vertex(uint32_t vertex) const {
    if (kWedgeRecent * std::size_t{vertex} < recent_.size())
      __builtin_prefetch(&recent_[kWedgeRecent * std::size_t{vertex}], 1);
  }
  // The current level's corner ids, 3 per face (what predict() reads of the arc's faces).
  const std::vector<uint32_t>& level_ids() const { return current_; }
  // Every id's units, components() per id (valid when known).
  const std::vector<uint32_t>& all_units() const { return units_; }
  std::size_t components() const { return components_; }

  // A corner before the splits (base and carried faces, in corner order): its vertex's
  // wedges. `level`: the face is one of the current level's (a base face), whose corner ids
  // the moved corners' predictions read.
  void pass(uint32_t vertex, uint32_t id, bool level) {
    if (level) current_.push_back(id);
    if (id == kNoAttribute) return;
    touch(vertex, id);
  }

  // The moved corner `slot` of level face f (whose vertices are `face`, u at slot), or a
  // corner of a new face (f = kNoAttribute), at `vertex`; v the new vertex, whose position
  // is known. `positions`: 3 units per vertex.
  struct ArcFace {
    uint32_t face;
    const uint32_t* vertices;
    int slot;  // u's
  };
  struct Corner {
    WedgeRole role;
    uint32_t vertex;
    // A moved corner: the new vertex, the split's moved faces in the arc's order, and which
    // of them the corner is in.
    uint32_t v = 0;
    const ArcFace* arc = nullptr;
    std::size_t arc_size = 0;
    std::size_t moved = 0;
  };

  // 2.4 (§5.11): a moved corner's new value is predicted through the arc face that holds v
  // best, and significant decimals (the positions', `position_numbers`, and the table's,
  // `value_numbers`, each null when not) by their values. After reset.
  void predict_by_values(const SignificantDecimals* position_numbers,
                         const SignificantDecimals* value_numbers) {
    by_values_ = true;
    position_numbers_ = position_numbers;
    value_numbers_ = value_numbers;
  }

  void encode(RangeEncoder& rc, const std::vector<uint32_t>& positions, const Corner& at,
              uint32_t id, const uint32_t* units) {
    WedgeModels& m = *models_;
    rc.bit(m.none[at.role], id == kNoAttribute ? 1 : 0);
    if (id == kNoAttribute) return finish(at, id);
    const uint32_t* recent = &recent_[kWedgeRecent * std::size_t{at.vertex}];
    const int remembered = remembered_of(recent);
    for (int k = 0; k < remembered; ++k) {
      const bool hit = recent[k] == id;
      rc.bit(m.recent[at.role][remembered][k], hit ? 1 : 0);
      if (hit) return finish(at, id);
    }
    const bool fresh = !ids_.known(id);
    if (ids_.unknown() > 0) rc.bit(m.fresh[at.role][remembered], fresh ? 1 : 0);
    if (fresh) {
      put_eg(rc, m.rank, ids_.rank(id));
      uint32_t predicted[3];
      const Prediction model = predict(positions, at, predicted);
      for (std::size_t c = 0; c < components_; ++c) {
        const int64_t residual = int64_t{units[c]} - int64_t{predicted[c]};
        const uint32_t context = value_context(model, c);
        put_eg(rc, m.value[model.kind][context], static_cast<uint64_t>(residual < 0 ? -residual : residual));
        if (residual != 0) rc.bit(m.sign[model.kind][context], residual < 0 ? 1 : 0);
      }
      std::copy(units, units + components_, units_.begin() + components_ * std::size_t{id});
      ids_.mark_known(id);
    } else {
      put_eg(rc, m.foreign, zigzag(int64_t{id} - previous_));
    }
    finish(at, id);
  }

  // False with `problem` set when the code names no id, an id out of range, one the corner's
  // other codes give, or a value beyond `top`.
  bool decode(RangeDecoder& rc, const std::vector<uint32_t>& positions, const Corner& at,
              uint32_t& id, std::string& problem) {
    WedgeModels& m = *models_;
    id = kNoAttribute;
    if (rc.bit(m.none[at.role]) != 0) return finish(at, id), true;
    const uint32_t* recent = &recent_[kWedgeRecent * std::size_t{at.vertex}];
    const int remembered = remembered_of(recent);
    for (int k = 0; k < remembered; ++k) {
      if (rc.bit(m.recent[at.role][remembered][k]) != 0) {
        id = recent[k];
        return finish(at, id), true;
      }
    }
    const bool fresh = ids_.unknown() > 0 && rc.bit(m.fresh[at.role][remembered]) != 0;
    if (fresh) {
      uint64_t rank = 0;
      if (!get_eg(rc, m.rank, rank) || rank >= ids_.unknown()) {
        problem = "introduces an id beyond those not yet known";
        return false;
      }
      id = ids_.select(static_cast<uint32_t>(rank));
      uint32_t predicted[3];
      const Prediction model = predict(positions, at, predicted);
      uint32_t* units = units_.data() + components_ * std::size_t{id};
      for (std::size_t c = 0; c < components_; ++c) {
        const uint32_t context = value_context(model, c);
        uint64_t magnitude = 0;
        if (!get_eg(rc, m.value[model.kind][context], magnitude) || magnitude > top_) {
          problem = "has an impossible value";
          return false;
        }
        const bool negative = magnitude != 0 && rc.bit(m.sign[model.kind][context]) != 0;
        const int64_t unit = int64_t{predicted[c]} + (negative ? -int64_t(magnitude) : int64_t(magnitude));
        if (unit < 0 || static_cast<uint64_t>(unit) > top_) {
          problem = "has a value beyond the grid";
          return false;
        }
        units[c] = static_cast<uint32_t>(unit);
      }
      ids_.mark_known(id);
    } else {
      uint64_t code = 0;
      if (!get_eg(rc, m.foreign, code) || code > (uint64_t{1} << 33)) {
        problem = "names an impossible id";
        return false;
      }
      const int64_t value = previous_ + unzigzag(code);
      if (value < 0 || value >= int64_t{count_} || !ids_.known(static_cast<uint32_t>(value))) {
        problem = "names id " + std::to_string(value) + ", which is not known here";
        return false;
      }
      id = static_cast<uint32_t>(value);
      if (std::find(recent, recent + remembered, id) != recent + remembered) {
        problem = "spells out id " + std::to_string(id) + ", which its vertex has (a shorter code)";
        return false;
      }
    }
    return finish(at, id), true;
  }

  // Face f's corner at `slot` (a moved corner) now holds `id`.
  void move(uint32_t face, int slot, uint32_t id) { current_[3 * std::size_t{face} + slot] = id; }

 private:
  static int remembered_of(const uint32_t* recent) {
    int n = 0;
    while (n < kWedgeRecent && recent[n] != kNoAttribute) ++n;
    return n;
  }

  void touch(uint32_t vertex, uint32_t id) {
    uint32_t* recent = &recent_[kWedgeRecent * std::size_t{vertex}];
    int k = 0;
    while (k < kWedgeRecent - 1 && recent[k] != id && recent[k] != kNoAttribute) ++k;
    for (; k > 0; --k) recent[k] = recent[k - 1];  // most recent first
    recent[0] = id;
    previous_ = id;
  }

  void finish(const Corner& at, uint32_t id) {
    if (at.role != kRoleMoved) current_.push_back(id);  // a new face's corner, in order
    if (id != kNoAttribute) touch(at.vertex, id);
  }

  // How a new id's value was predicted: kind 0 through the map of `face` (u at `slot`),
  // kind 1 from one value.
  struct Prediction {
    int kind = 1;
    uint32_t face = kNoAttribute;
    int slot = 0;
  };

  // The value a new id is predicted to have.
  //
  // A moved corner: the face (u, a, b) had ids s, ia, ib at u, a, b. Its texture map sends
  // u + alpha (a - u) + beta (b - u) to T(s) + alpha (T(ia) - T(s)) + beta (T(ib) - T(s));
  // alpha and beta are those of the least-squares fit of v - u in the face's plane, so the
  // prediction is where the map sends v. In 2.2 and 2.3 the face is the corner's own; in 2.4
  // it is, of the arc's faces with id s at u and ids at a and b, the one that holds v best:
  // whose largest of -alpha, -beta and alpha + beta - 1 (how far v lies outside it) is the
  // smallest, the first in the arc's order on ties. v lies in one of the arc's faces' sectors
  // (the faces it takes from u), where the map of that face is an interpolation rather than
  // the extrapolation of a face beside it: on spot, the residuals fall by a third. Without a
  // texture map (normals, or a corner without ids): T(s).
  // A new face's corner: its vertex's latest value, else the latest id's.
  Prediction predict(const std::vector<uint32_t>& positions, const Corner& at, uint32_t* out) const {
    uint32_t source = kNoAttribute;
    Prediction made;
    if (at.role == kRoleMoved) {
      const ArcFace& own = at.arc[at.moved];
      const uint32_t s = current_[3 * std::size_t{own.face} + own.slot];
      source = s;
      if (components_ == 2 && s != kNoAttribute) {
        const ArcFace* faces = by_values_ ? at.arc : &own;
        const std::size_t count = by_values_ ? at.arc_size : 1;
        FaceMap best;
        for (std::size_t k = 0; k < count; ++k) {
          const std::size_t base = 3 * std::size_t{faces[k].face};
          if (current_[base + faces[k].slot] != s) continue;
          FaceMap map;
          map.ia = current_[base + (faces[k].slot + 1) % 3];
          map.ib = current_[base + (faces[k].slot + 2) % 3];
          if (map.ia == kNoAttribute || map.ib == kNoAttribute) continue;
          if (!fit(positions, faces[k], at.v, map)) continue;
          if (best.det == 0 || map.outside * best.det < best.outside * map.det) {
            best = map;
            made.face = faces[k].face;
            made.slot = faces[k].slot;
          }
        }
        if (best.det != 0) {
          apply(best, s, out);
          made.kind = 0;
          return made;
        }
      }
    } else {
      source = recent_[kWedgeRecent * std::size_t{at.vertex}];
    }
    if (source == kNoAttribute && count_ > 0 && previous_ >= 0 && previous_ < int64_t{count_} &&
        ids_.known(static_cast<uint32_t>(previous_))) {
      source = static_cast<uint32_t>(previous_);
    }
    for (std::size_t c = 0; c < components_; ++c)
      out[c] = source == kNoAttribute ? 0 : units_[components_ * std::size_t{source} + c];
    return made;
  }

  // A face's map: alpha = na / det, beta = nb / det; `outside` = max(-na, -nb, na + nb - det).
  struct FaceMap {
    uint32_t ia = kNoAttribute, ib = kNoAttribute;
    int64_t na = 0, nb = 0, det = 0;
    __int128 outside = 0;
  };

  // The least-squares alpha and beta of v - u in the face's plane. Coordinates (2.4:
  // significant decimals as their values, all twelve on one scale, §5.3) are first halved
  // together until each difference is below 2^14, so that the normal equations fit in 64 bits.
  bool fit(const std::vector<uint32_t>& positions, const ArcFace& face, uint32_t v, FaceMap& map) const {
    const uint32_t corners[4] = {face.vertices[face.slot], face.vertices[(face.slot + 1) % 3],
                                 face.vertices[(face.slot + 2) % 3], v};  // u, a, b, v
    const auto unit_at = [&](std::size_t k) {
      return positions[3 * std::size_t{corners[k / 3]} + k % 3];
    };
    const int64_t scale = position_numbers_ != nullptr ? position_numbers_->scale_of(12, unit_at) : 0;
    const auto at = [&](int corner, int c) {
      const uint32_t unit = unit_at(3 * std::size_t(corner) + c);
      return position_numbers_ != nullptr ? position_numbers_->linear(unit, scale) : int64_t{unit};
    };
    int64_t nine[9];  // e1 = a - u, e2 = b - u, d = v - u
    int64_t *e1 = nine, *e2 = nine + 3, *d = nine + 6;
    for (int c = 0; c < 3; ++c) {
      const int64_t pu = at(0, c);
      e1[c] = at(1, c) - pu;
      e2[c] = at(2, c) - pu;
      d[c] = at(3, c) - pu;
    }
    halve_below(nine, 9, 14);
    // Each dot product below 3 * 2^28; each product of two below 2^60.
    const int64_t g11 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
    const int64_t g12 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
    const int64_t g22 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
    const int64_t b1 = e1[0] * d[0] + e1[1] * d[1] + e1[2] * d[2];
    const int64_t b2 = e2[0] * d[0] + e2[1] * d[1] + e2[2] * d[2];
    const int64_t det = g11 * g22 - g12 * g12;
    if (det <= 0) return false;
    // Each of alpha and beta clamped to [-4, 4]: a sliver's map is no guide.
    map.det = det;
    map.na = std::clamp(g22 * b1 - g12 * b2, -4 * det, 4 * det);
    map.nb = std::clamp(g11 * b2 - g12 * b1, -4 * det, 4 * det);
    map.outside = std::max({static_cast<__int128>(-map.na), static_cast<__int128>(-map.nb),
                            static_cast<__int128>(map.na) + map.nb - det});
    return true;
  }

  // Where the map sends v: T(s) + (na (T(ia) - T(s)) + nb (T(ib) - T(s))) / det, rounded (the
  // last products take 128 bits); 2.4's significant decimals as their values, the three on
  // one scale per component, then the nearest number (§5.3).
  void apply(const FaceMap& map, uint32_t s, uint32_t* out) const {
    const uint32_t *ts = units(s), *ta = units(map.ia), *tb = units(map.ib);
    for (std::size_t c = 0; c < 2; ++c) {
      if (value_numbers_ != nullptr) {
        const uint32_t three[3] = {ts[c], ta[c], tb[c]};
        const int64_t scale = value_numbers_->scale_of(3, [&](std::size_t k) { return three[k]; });
        const int64_t ls = value_numbers_->linear(ts[c], scale);
        const __int128 num =
            static_cast<__int128>(map.na) * (value_numbers_->linear(ta[c], scale) - ls) +
            static_cast<__int128>(map.nb) * (value_numbers_->linear(tb[c], scale) - ls);
        out[c] = value_numbers_->nearest(ls + rounded_quotient(num, map.det), scale);
        continue;
      }
      const __int128 num = static_cast<__int128>(map.na) * (int64_t{ta[c]} - int64_t{ts[c]}) +
                           static_cast<__int128>(map.nb) * (int64_t{tb[c]} - int64_t{ts[c]});
      const __int128 q = rounded_quotient(num, map.det);
      const __int128 unit = std::clamp<__int128>(ts[c] + q, 0, static_cast<__int128>(top_));
      out[c] = static_cast<uint32_t>(unit);
    }
  }

  // The bit length of the face's spread in component c (through a face's map), or 0.
  uint32_t value_context(const Prediction& made, std::size_t c) const {
    if (made.kind != 0) return 0;
    const std::size_t base = 3 * std::size_t{made.face};
    const uint32_t s = current_[base + made.slot], ia = current_[base + (made.slot + 1) % 3],
                   ib = current_[base + (made.slot + 2) % 3];
    const int64_t ts = units(s)[c];
    const auto magnitude = [](int64_t x) { return static_cast<uint64_t>(x < 0 ? -x : x); };
    const uint64_t spread = magnitude(int64_t{units(ia)[c]} - ts) + magnitude(int64_t{units(ib)[c]} - ts);
    uint32_t n = 0;
    while ((spread >> n) != 0) ++n;
    return std::min<uint32_t>(n, kWedgeValueContexts - 1);
  }

  std::size_t components_ = 2;
  uint32_t count_ = 0;
  uint64_t top_ = 0;
  std::vector<uint32_t> units_;    // components per id, valid when known
  UnknownIds ids_;
  std::vector<uint32_t> recent_;   // kWedgeRecent per vertex, most recent first
  std::vector<uint32_t> current_;  // 3 per face of the level: its corners' ids
  int64_t previous_ = 0;           // the latest id of any corner
  bool by_values_ = false;         // 2.4 (predict_by_values)
  const SignificantDecimals* position_numbers_ = nullptr;
  const SignificantDecimals* value_numbers_ = nullptr;
  std::unique_ptr<WedgeModels> models_;
};

}  // namespace pm::detail
