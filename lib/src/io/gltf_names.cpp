#include "io/gltf_names.h"

#include <algorithm>
#include <set>

namespace pm::detail {
namespace {

bool usable(const std::string& name) {
  if (name.empty() || name.front() == ' ' || name.front() == '\t' || name.back() == ' ' || name.back() == '\t')
    return false;
  return std::none_of(name.begin(), name.end(), [](char c) {
    return c == '#' || (static_cast<unsigned char>(c) < 0x20) || c == 0x7f;
  });
}

}  // namespace

std::vector<std::string> unique_material_names(const std::vector<std::string>& raw) {
  std::vector<std::string> names(raw.size());
  std::set<std::string> taken;
  // Own names first, in order, so that a fallback never takes a name a later material has.
  for (std::size_t i = 0; i < raw.size(); ++i)
    if (usable(raw[i]) && taken.insert(raw[i]).second) names[i] = raw[i];
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (!names[i].empty()) continue;
    std::string name = "material_" + std::to_string(i);
    while (!taken.insert(name).second) name += '_';
    names[i] = name;
  }
  return names;
}

}  // namespace pm::detail
