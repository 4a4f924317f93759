// The GLB container (glTF 2.0 specification, Khronos 2017/2021, §4.4 "Structure"): a 12-byte
// header (magic "glTF", version 2, total length), then chunks of 8-byte headers (length,
// type) whose data is padded to 4 bytes: the JSON chunk first, then at most one BIN chunk.
// Checked here, every length against the bytes there are, before anything else reads them.
#pragma once

#include <string>
#include <string_view>

#include "pm/status.h"

namespace pm::detail {

// Starts with the GLB magic "glTF".
bool is_glb(std::string_view bytes);

struct GlbChunks {
  std::string_view json;
  std::string_view binary;   // the BIN chunk's data (padding included), or empty
  bool has_binary = false;
  std::string_view whole;    // the header's length worth of bytes: what a GLB parser may read
  std::size_t trailing = 0;  // bytes after that length (ignored)
};

// kParseError naming what is wrong: a header or chunk that ends past the bytes, a version
// other than 2, a first chunk that is not JSON, a second that is not BIN.
Status split_glb(std::string_view bytes, GlbChunks& chunks);

// A GLB of `json` (padded with spaces) and `binary` (padded with zeros; no BIN chunk when
// empty), as §4.4 lays it out.
std::string make_glb(std::string_view json, std::string_view binary);

}  // namespace pm::detail
