// Encodes a literal square (two triangles on a boundary) and decodes its full detail.
#include <pm/encoder.h>
#include <pm/lod.h>
#include <pm/pm_codec.h>

#include <cstdio>

int main() {
  pm::Mesh square;
  square.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 0.5f, 0};
  square.triangles = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
  pm::ProgressiveMesh progressive;
  std::string bytes;
  if (!pm::encode(square, {}, progressive) || !pm::write_pm(progressive, {}, bytes) ||
      !pm::read_pm(bytes, progressive))
    return 1;
  const pm::Mesh full = pm::extract_level(progressive, progressive.split_count());
  std::printf("%zu faces, %zu splits\n", full.face_count(), progressive.split_count());
  return full.face_count() == 4 && progressive.split_count() >= 1 &&
                 progressive.base_face_count() < 4
             ? 0
             : 1;
}
