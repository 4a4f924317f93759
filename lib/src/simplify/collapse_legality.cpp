#include "simplify/collapse_legality.h"

#include <algorithm>

#include "simplify/geometry.h"

namespace pm {

bool face_keeps_geometry(const Vec3 before[3], const Vec3 after[3], double cos_max_flip) {
  // Relative threshold for a degenerate face: |a x b| below this times the squared
  // longest edge means the triangle is thinner than float32 can represent faithfully.
  constexpr double kDegenerate = 1e-10;
  const Vec3 n0 = area_vector(before[0], before[1], before[2]);
  const Vec3 n1 = area_vector(after[0], after[1], after[2]);
  const double longest = std::max({(after[1] - after[0]).sqrnorm(), (after[2] - after[1]).sqrnorm(),
                                   (after[0] - after[2]).sqrnorm()});
  const double len1 = n1.norm();
  if (len1 <= kDegenerate * longest) return false;
  const double len0 = n0.norm();
  return !(len0 > 0 && (n0 | n1) < cos_max_flip * len0 * len1);
}

std::set<std::pair<uint32_t, uint32_t>> carried_edges(const ManifoldMesh& repaired) {
  std::set<std::pair<uint32_t, uint32_t>> edges;
  const auto& f = repaired.carried_faces;
  for (std::size_t i = 0; i + 2 < f.size(); i += 3)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = f[i + k], b = f[i + (k + 1) % 3];
      if (a != b) edges.insert({std::min(a, b), std::max(a, b)});
    }
  return edges;
}

WeldGroups weld_groups(const ManifoldMesh& repaired) {
  WeldGroups welds;
  const std::size_t n = repaired.canonical.size();
  for (uint32_t x = 0; x < n; ++x) {
    const uint32_t c = repaired.canonical[x];
    if (c == x) continue;
    if (welds.group.empty()) {
      welds.group.assign(n, -1);
      welds.members.resize(n);
    }
    if (welds.group[c] < 0) {
      welds.group[c] = static_cast<int>(c);
      welds.members[c].push_back(c);
    }
    welds.group[x] = static_cast<int>(c);
    welds.members[c].push_back(x);
  }
  return welds;
}

}  // namespace pm
