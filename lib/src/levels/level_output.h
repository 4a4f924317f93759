// How a level of detail's corner attributes are written (lod.cpp, selective_refinement.cpp):
// the ids renumbered into the output's own value table. At full detail the table is the
// input's whole table, so ids come back as the input wrote them; at other levels it holds
// the values the level uses, in the order of the input's table. Internal.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "pm/mesh.h"  // kNoAttribute

namespace pm::detail {

inline void output_attribute(const std::vector<uint32_t>& ids, const std::vector<float>& table,
                             std::size_t dims, bool full, std::vector<float>& out_table,
                             std::vector<uint32_t>& out_ids) {
  const std::size_t count = table.size() / dims;
  std::vector<uint32_t> new_id(count, kNoAttribute);
  if (full) {
    for (std::size_t i = 0; i < count; ++i) new_id[i] = static_cast<uint32_t>(i);
    out_table = table;
  } else {
    for (uint32_t id : ids)
      if (id != kNoAttribute) new_id[id] = 0;
    uint32_t next = 0;
    for (std::size_t i = 0; i < count; ++i) {
      if (new_id[i] == kNoAttribute) continue;
      new_id[i] = next++;
      out_table.insert(out_table.end(), table.begin() + dims * i, table.begin() + dims * (i + 1));
    }
  }
  out_ids.resize(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i)
    out_ids[i] = ids[i] == kNoAttribute ? kNoAttribute : new_id[ids[i]];
}

}  // namespace pm::detail
