#include "pm/version.h"

namespace pm {

const char* version() { return PM_VERSION_STRING; }

}  // namespace pm
