#include "io/openmesh_logs.h"

#include <OpenMesh/Core/System/omstream.hh>
#include <mutex>

namespace pm {

void silence_openmesh_logs() {
  static std::once_flag once;
  std::call_once(once, [] {
    omerr().disable();
    omlog().disable();
    omout().disable();
  });
}

}  // namespace pm
