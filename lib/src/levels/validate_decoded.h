// validate() for the .pm reader's own output (internal to the library).
#pragma once

#include <string>

#include "pm/progressive_mesh.h"

namespace pm::detail {

// validate() without its replay of the moved faces. For a mesh the 2.x reader has just
// decoded: it replayed every split on its own connectivity (formats/split_fans.h), where a
// ring-coded split's moved faces are an arc of u's fan (faces that hold u once, each once)
// and an explicit split's are checked one by one (each holds u once, none twice), so the
// replay would find nothing more, given base faces in range and without a repeated vertex,
// which this checks. Everything else validate() checks, this checks. The reader's fuzz
// target holds it to that: validate() accepts whatever read_pm returns.
bool validate_decoded(const ProgressiveMesh& pm, std::string* message);

}  // namespace pm::detail
