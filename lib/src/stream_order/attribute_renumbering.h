// Renumbering a texture-coordinate or normal table: entry id becomes new_id[id] (or is
// dropped, kNoAttribute), and every corner id that names it follows. Shared by the table
// order the encoder chooses (order_attribute_tables) and the reader's prefixes, which drop
// the entries whose values have not arrived (pm-format.md §7). Internal.
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <vector>

#include "pm/mesh.h"  // kNoAttribute

namespace pm::detail {

// new_id: one per entry, each below new_count or kNoAttribute; no corner may name a
// dropped entry.
inline void renumber_entries(std::vector<float>& table, std::size_t components,
                             const std::vector<uint32_t>& new_id, uint32_t new_count,
                             std::initializer_list<std::vector<uint32_t>*> corner_ids) {
  std::vector<float> renumbered(components * std::size_t{new_count});
  for (std::size_t id = 0; id < new_id.size(); ++id) {
    if (new_id[id] == kNoAttribute) continue;
    for (std::size_t c = 0; c < components; ++c)
      renumbered[components * new_id[id] + c] = table[components * id + c];
  }
  table = std::move(renumbered);
  for (std::vector<uint32_t>* ids : corner_ids) {
    for (uint32_t& id : *ids) {
      if (id != kNoAttribute) id = new_id[id];
    }
  }
}

}  // namespace pm::detail
