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
  struct Corner {
    WedgeRole role;
    uint32_t vertex;
    uint32_t face = kNoAttribute;
    const uint32_t* face_vertices = nullptr;
    int slot = 0;
    uint32_t v = 0;
  };

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
      const int model = predict(positions, at, predicted);
      for (std::size_t c = 0; c < components_; ++c) {
        const int64_t residual = int64_t{units[c]} - int64_t{predicted[c]};
        const uint32_t context = value_context(at, c, model);
        put_eg(rc, m.value[model][context], static_cast<uint64_t>(residual < 0 ? -residual : residual));
        if (residual != 0) rc.bit(m.sign[model][context], residual < 0 ? 1 : 0);
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
      const int model = predict(positions, at, predicted);
      uint32_t* units = units_.data() + components_ * std::size_t{id};
      for (std::size_t c = 0; c < components_; ++c) {
        const uint32_t context = value_context(at, c, model);
        uint64_t magnitude = 0;
        if (!get_eg(rc, m.value[model][context], magnitude) || magnitude > top_) {
          problem = "has an impossible value";
          return false;
        }
        const bool negative = magnitude != 0 && rc.bit(m.sign[model][context]) != 0;
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

  // The value a new id is predicted to have; 0 through the face's map, 1 from one value.
  //
  // A moved corner: the face (u, a, b) had ids s, ia, ib at u, a, b. Its texture map sends
  // u + alpha (a - u) + beta (b - u) to T(s) + alpha (T(ia) - T(s)) + beta (T(ib) - T(s));
  // alpha and beta are those of the least-squares fit of v - u in the face's plane, so the
  // prediction is where the map sends v. Coordinates are first halved together until each
  // difference is below 2^14, so that the normal equations fit in 64 bits; the last product
  // takes 128. Without a texture map (normals, or a corner without ids): T(s).
  // A new face's corner: its vertex's latest value, else the latest id's.
  int predict(const std::vector<uint32_t>& positions, const Corner& at, uint32_t* out) const {
    uint32_t source = kNoAttribute;
    if (at.role == kRoleMoved) {
      const std::size_t base = 3 * std::size_t{at.face};
      const uint32_t s = current_[base + at.slot];
      const uint32_t ia = current_[base + (at.slot + 1) % 3], ib = current_[base + (at.slot + 2) % 3];
      source = s;
      if (components_ == 2 && s != kNoAttribute && ia != kNoAttribute && ib != kNoAttribute &&
          map_through(positions, at, s, ia, ib, out)) {
        return 0;
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
    return 1;
  }

  bool map_through(const std::vector<uint32_t>& positions, const Corner& at, uint32_t s, uint32_t ia,
                   uint32_t ib, uint32_t* out) const {
    const uint32_t u = at.face_vertices[at.slot], a = at.face_vertices[(at.slot + 1) % 3],
                   b = at.face_vertices[(at.slot + 2) % 3];
    int64_t e1[3], e2[3], d[3];
    for (int c = 0; c < 3; ++c) {
      const int64_t pu = positions[3 * std::size_t{u} + c];
      e1[c] = int64_t{positions[3 * std::size_t{a} + c]} - pu;
      e2[c] = int64_t{positions[3 * std::size_t{b} + c]} - pu;
      d[c] = int64_t{positions[3 * std::size_t{at.v} + c]} - pu;
    }
    const auto magnitude = [](int64_t x) { return x < 0 ? -x : x; };
    int64_t largest = 0;
    for (int c = 0; c < 3; ++c)
      largest = std::max({largest, magnitude(e1[c]), magnitude(e2[c]), magnitude(d[c])});
    int halvings = 0;
    while ((largest >> halvings) >= (int64_t{1} << 14)) ++halvings;
    const auto halve = [&](int64_t x) { return x < 0 ? -(-x >> halvings) : x >> halvings; };
    for (int c = 0; c < 3; ++c) e1[c] = halve(e1[c]), e2[c] = halve(e2[c]), d[c] = halve(d[c]);
    // Each dot product below 3 * 2^28; each product of two below 2^60.
    const int64_t g11 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
    const int64_t g12 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
    const int64_t g22 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
    const int64_t b1 = e1[0] * d[0] + e1[1] * d[1] + e1[2] * d[2];
    const int64_t b2 = e2[0] * d[0] + e2[1] * d[1] + e2[2] * d[2];
    const int64_t det = g11 * g22 - g12 * g12;
    if (det <= 0) return false;
    // alpha = na / det, beta = nb / det, each clamped to [-4, 4]: a sliver's map is no guide.
    const int64_t na = std::clamp(g22 * b1 - g12 * b2, -4 * det, 4 * det);
    const int64_t nb = std::clamp(g11 * b2 - g12 * b1, -4 * det, 4 * det);
    const uint32_t *ts = units(s), *ta = units(ia), *tb = units(ib);
    for (std::size_t c = 0; c < 2; ++c) {
      const __int128 num = static_cast<__int128>(na) * (int64_t{ta[c]} - int64_t{ts[c]}) +
                           static_cast<__int128>(nb) * (int64_t{tb[c]} - int64_t{ts[c]});
      // The nearest integer to num / det, halves up (floor of (2 num + det) / (2 det)).
      const __int128 twice = 2 * num + det, den = 2 * static_cast<__int128>(det);
      __int128 q = twice / den;
      if (twice % den != 0 && twice < 0) --q;
      const __int128 unit = std::clamp<__int128>(ts[c] + q, 0, static_cast<__int128>(top_));
      out[c] = static_cast<uint32_t>(unit);
    }
    return true;
  }

  // The bit length of the face's spread in component c (through a face's map), or 0.
  uint32_t value_context(const Corner& at, std::size_t c, int model) const {
    if (model != 0) return 0;
    const std::size_t base = 3 * std::size_t{at.face};
    const uint32_t s = current_[base + at.slot], ia = current_[base + (at.slot + 1) % 3],
                   ib = current_[base + (at.slot + 2) % 3];
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
  std::unique_ptr<WedgeModels> models_;
};

}  // namespace pm::detail
