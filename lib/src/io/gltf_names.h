// The material names pm gives a glTF file's materials, shared by the reader (which names the
// faces' materials) and the writer (which finds a material source's definitions by name).
#pragma once

#include <string>
#include <vector>

namespace pm::detail {

// By material index: the material's own name (`raw[i]`) when it is usable, else
// "material_N" (N its index). Usable: not empty, read back from an OBJ `usemtl` as itself (no
// control characters, no '#', no blank at an end) and not taken by an earlier material. A
// fallback that is taken (a material named "material_3") gets '_' appended until it is not.
std::vector<std::string> unique_material_names(const std::vector<std::string>& raw);

}  // namespace pm::detail
