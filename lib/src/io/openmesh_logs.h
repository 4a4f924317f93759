// OpenMesh writes warnings to its log streams (omerr, omlog, omout); the library never
// prints, so it turns them off. OpenMesh 9 creates those streams lazily and without a lock,
// so two threads touching them first at once can crash: this does it once per process,
// under std::call_once, before any OpenMesh call of the library.
#pragma once

namespace pm {

void silence_openmesh_logs();

}  // namespace pm
