// libFuzzer target: the OFF reader, and on every mesh it accepts the writer round trip and
// (for small meshes) the encoder, LOD extraction and .pm round trip (see fuzz_common.h).
#include <cstddef>
#include <cstdint>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return pm::fuzz::fuzz_mesh_reader(data, size, pm::MeshFormat::kOff);
}
