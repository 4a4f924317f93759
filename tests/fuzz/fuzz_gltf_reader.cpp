// libFuzzer target: the glTF reader (read_gltf, .glb and .gltf by their first bytes), from
// memory (an external buffer is refused, never opened), with a face limit low enough that no
// instancing can ask for more memory than libFuzzer allows. On every mesh it accepts: the
// mesh is valid, and write_gltf's output reads back to the same faces, positions bit for bit.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_common.h"
#include "pm/gltf.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pm;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  GltfReadOptions options;
  options.max_faces = std::size_t{1} << 16;
  Mesh mesh;
  ReadReport report;
  const Status status = read_gltf(bytes, options, mesh, &report);
  if (!status) {
    fuzz::check_error(status, "read_gltf");
    return 0;
  }
  fuzz::check_mesh(mesh, "read_gltf: face index out of range");
  if (const Status valid = validate_attributes(mesh); !valid) {
    fuzz::fail("read_gltf gave an invalid mesh: " + valid.message());
  }
  for (bool quantize : {false, true}) {
    GltfWriteOptions write_options;
    write_options.quantize = quantize;
    std::string written;
    const Status write_status = write_gltf({{&mesh, 0}}, write_options, written);
    if (!write_status) fuzz::fail("write_gltf of a read mesh: " + write_status.message());
    Mesh back;
    const Status back_status = read_gltf(written, options, back);
    if (!back_status) fuzz::fail("read_gltf of write_gltf's output: " + back_status.message());
    if (!quantize)
      fuzz::check(fuzz::canonical_faces(back) == fuzz::canonical_faces(mesh),
                  "read_gltf(write_gltf(mesh)) has other faces");
    else
      fuzz::check(back.face_count() == mesh.face_count(), "quantized round trip: face count");
  }
  return 0;
}
