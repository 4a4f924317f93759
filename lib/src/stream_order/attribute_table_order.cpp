// The texture-coordinate and normal tables in the order in which a decoder first meets
// their entries (pm-format.md §5.11: base corners, carried corners, then split by split its
// moved corners and its new faces' corners), entries no corner uses last. A .pm stream
// (2.2) names an entry met for the first time by its rank among those not met yet, so in
// this order every such name is 0, and the entry's value is coded where it is met,
// predicted from its face. Without it the names cost
// about log2 of the table's size each.
#include <cstdint>
#include <vector>

#include "stream_order/attribute_renumbering.h"
#include "pm/advanced/stream_order.h"
#include "pm/progressive_mesh.h"

namespace pm {
namespace {

void reorder(std::vector<float>& table, std::size_t components, std::vector<uint32_t>& face_ids,
             std::vector<uint32_t>& moved_ids, const ProgressiveMesh& pm) {
  const std::size_t count = table.size() / components;
  if (count == 0 || face_ids.empty()) return;
  constexpr uint32_t kUnseen = 0xFFFFFFFFu;
  std::vector<uint32_t> new_id(count, kUnseen);
  uint32_t next = 0;
  const auto meet = [&](uint32_t id) {
    if (id != kNoAttribute && new_id[id] == kUnseen) new_id[id] = next++;
  };
  // Corner order (§5.1): base faces, carried faces (last in face_ids), then the splits.
  const std::size_t base_corners = pm.base_faces.size();
  const std::size_t carried_corners = pm.carried_faces.size();
  for (std::size_t k = 0; k < base_corners; ++k) meet(face_ids[k]);
  for (std::size_t k = face_ids.size() - carried_corners; k < face_ids.size(); ++k) meet(face_ids[k]);
  std::size_t next_corner = base_corners;
  for (const VertexSplit& split : pm.splits) {
    for (uint32_t k = 0; k < split.moved_count; ++k) meet(moved_ids[split.moved_begin + k]);
    for (uint32_t k = 0; k < 3 * split.new_face_count(); ++k) meet(face_ids[next_corner++]);
  }
  for (uint32_t& id : new_id) {
    if (id == kUnseen) id = next++;  // entries no corner uses, in their order
  }
  detail::renumber_entries(table, components, new_id, next, {&face_ids, &moved_ids});
}

}  // namespace

void order_attribute_tables(ProgressiveMesh& pm) {
  if (pm.keeps_order()) return;  // full detail must list the tables as the input did
  reorder(pm.uvs, 2, pm.face_uvs, pm.moved_uvs, pm);
  reorder(pm.normals, 3, pm.face_normals, pm.moved_normals, pm);
}

}  // namespace pm
