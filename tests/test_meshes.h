// The meshes the acceptance tests run on: every real mesh of ../shared/meshes and every
// sample the project ships. Names are fixed so that each becomes its own test case.
#pragma once

#include <string>
#include <vector>

#include "test_util.h"

namespace pm::test {

struct TestMesh {
  std::string name;  // "bunny" style, usable in a test name
  std::string path;
  bool shared;  // from ../shared/meshes (skipped when absent)
};

inline std::vector<TestMesh> all_test_meshes() {
  std::vector<TestMesh> meshes;
  for (const char* file : {"armadillo.off", "cow.obj", "fandisk.obj", "homer.obj", "nefertiti.obj",
                           "rocker-arm.obj", "spot.obj", "stanford-bunny.obj"}) {
    std::string name = file;
    name = name.substr(0, name.find('.'));
    for (char& c : name)
      if (c == '-') c = '_';
    meshes.push_back({name, shared_mesh_path(file), true});
  }
  for (const char* file : {"sphere.obj", "terrain_holes.obj", "block_features.obj",
                           "nonmanifold.obj", "polygons.obj", "textured.obj"}) {
    std::string name = std::string("sample_") + file;
    name = name.substr(0, name.find('.'));
    meshes.push_back({name, sample_mesh_path(file), false});
  }
  return meshes;
}

inline std::string test_mesh_name(const ::testing::TestParamInfo<TestMesh>& info) {
  return info.param.name;
}

}  // namespace pm::test

// Skips a parameterized test on a real mesh when ../shared/meshes is absent.
#define PM_SKIP_IF_MISSING(mesh)               \
  do {                                         \
    if ((mesh).shared) PM_SKIP_IF_NO_SHARED(); \
  } while (false)

namespace pm::test {
// GoogleTest prints parameters with this instead of a byte dump.
inline void PrintTo(const TestMesh& mesh, std::ostream* out) {
  *out << mesh.path;
}
}  // namespace pm::test
