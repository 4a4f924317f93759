// pmesh.Error: a failed pm::Status as a Python exception that carries the library's stable
// code name ("parse-error", ...; pm::error_code_name), so that a script can branch on it.
#pragma once

#include <exception>
#include <string>
#include <utility>

#include "pm/status.h"

namespace pmesh {

// Thrown by the binding; the module's exception translator raises it as pmesh.Error.
class Error : public std::exception {
 public:
  Error(std::string code, std::string message)
      : code_(std::move(code)), message_(std::move(message)) {}
  const char* what() const noexcept override { return message_.c_str(); }
  const std::string& code() const { return code_; }
  const std::string& message() const { return message_; }

 private:
  std::string code_;
  std::string message_;
};

// Throws a failed status as Error; `where` (a file name, an argument) prefixes its message,
// as the tools print it: "bunny.obj: line 12: ...".
inline void throw_if_failed(const pm::Status& status, const std::string& where = "") {
  if (status) return;
  throw Error(pm::error_code_name(status.code()),
              where.empty() ? status.message() : where + ": " + status.message());
}

// A caller's argument the binding refuses before calling the library.
[[noreturn]] inline void invalid_argument(const std::string& message) {
  throw Error(pm::error_code_name(pm::ErrorCode::kInvalidArgument), message);
}

}  // namespace pmesh
