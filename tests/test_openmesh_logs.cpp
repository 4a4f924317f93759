// No process-wide side effect (issue 27): the library turns OpenMesh's log streams (omerr,
// omlog, omout) off while it calls OpenMesh, so that it never prints, and leaves them as the
// caller had them, whatever that was.
#include <gtest/gtest.h>

#include <OpenMesh/Core/System/omstream.hh>

#include <sstream>
#include <string>

#include "pm/encoder.h"
#include "pm/mesh_io.h"
#include "test_util.h"

namespace pm {
namespace {

struct LogStates {
  bool err, log, out;
  bool operator==(const LogStates& o) const {
    return err == o.err && log == o.log && out == o.out;
  }
};

LogStates current() { return {omerr().is_enabled(), omlog().is_enabled(), omout().is_enabled()}; }

void set(const LogStates& s) {
  s.err ? omerr().enable() : omerr().disable();
  s.log ? omlog().enable() : omlog().disable();
  s.out ? omout().enable() : omout().disable();
}

// A complex edge (three faces on one edge) and a pinched vertex: faces OpenMesh rejects and
// reports on omerr when its log is on, which the repair handles.
Mesh non_manifold() {
  Mesh mesh;
  mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 2, 2, 0, 3, 2, 0};
  mesh.triangles = {0, 1, 2, 1, 0, 3, 0, 1, 4, 1, 5, 6};
  return mesh;
}

const std::string kStl =
    "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
    "endloop\nendfacet\nendsolid t\n";

TEST(OpenMeshLogs, EncodeAndTheReadersLeaveTheStreamsAsTheCallerLeftThem) {
  const LogStates before = current();
  for (const LogStates& caller : {LogStates{true, true, true}, LogStates{true, false, true},
                                  LogStates{false, true, false}, LogStates{false, false, false}}) {
    set(caller);
    ProgressiveMesh pm;
    EncodeStats stats;
    ASSERT_TRUE(test::ok(encode(non_manifold(), EncodeOptions{}, pm, &stats)));
    EXPECT_TRUE(stats.repair.any());  // the repair ran, through OpenMesh
    EXPECT_EQ(current(), caller) << "after encode()";
    Mesh stl;
    ASSERT_TRUE(test::ok(read_mesh_from_memory(kStl, MeshFormat::kStl, stl)));
    EXPECT_EQ(current(), caller) << "after reading an STL file";
  }
  // (No stream is connected to capture the output: OpenMesh's disconnect() leaks the
  // target it made, which LeakSanitizer reports.)
  set(before);
}

}  // namespace
}  // namespace pm
