// Internal entry points of the mesh readers; mesh_io.cpp dispatches to them by format.
#pragma once

#include <string_view>

#include "pm/mesh.h"
#include "pm/mesh_io.h"
#include "pm/status.h"

namespace pm::detail {

// Our own OBJ parser (obj_reader.cpp). On success fills `mesh` and `report` (both are
// overwritten, not appended to); on failure leaves them in an unspecified state, so callers
// parse into a scratch mesh.
Status read_obj(std::string_view bytes, Mesh& mesh, ReadReport& report);

}  // namespace pm::detail
