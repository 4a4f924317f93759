// The library's version, for a program or a binding to report.
#pragma once

namespace pm {

// The linked library's version, "major.minor.patch": the project's (CMakeLists.txt), the one
// pmenc --version and pmdec --version print.
const char* version();

}  // namespace pm
