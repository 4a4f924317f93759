// The indexed triangle mesh that goes in and comes out of the library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pm {

// A triangle soup with shared vertices: no topology is implied or required. Input
// readers produce it; LOD extraction produces it; writers consume it.
struct Mesh {
  std::vector<float> positions;     // x, y, z per vertex (float32, as stored in files)
  std::vector<uint32_t> triangles;  // three vertex indices per face, counter-clockwise

  std::size_t vertex_count() const { return positions.size() / 3; }
  std::size_t face_count() const { return triangles.size() / 3; }
};

}  // namespace pm
