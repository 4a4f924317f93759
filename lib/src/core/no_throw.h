// The library's promise (status.h): no exception leaves a function that returns a Status.
// Allocation failure becomes kResourceLimit at the public entry points, through this.
#pragma once

#include <new>
#include <stdexcept>
#include <utility>

#include "pm/status.h"

namespace pm::detail {

// Runs `body` (which returns a Status) and turns std::bad_alloc, and std::length_error (a
// container asked for more than it can hold), into kResourceLimit "out of memory".
template <class Body>
Status no_throw(Body&& body) {
  try {
    return std::forward<Body>(body)();
  } catch (const std::bad_alloc&) {
  } catch (const std::length_error&) {
  }
  return Status(ErrorCode::kResourceLimit, "out of memory");  // short: no allocation
}

}  // namespace pm::detail
