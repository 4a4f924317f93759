#include "pm/status.h"

namespace pm {

const char* error_code_name(ErrorCode code) {
  switch (code) {
    case ErrorCode::kOk:
      return "ok";
    case ErrorCode::kInvalidArgument:
      return "invalid-argument";
    case ErrorCode::kIoError:
      return "io-error";
    case ErrorCode::kParseError:
      return "parse-error";
    case ErrorCode::kUnsupportedFormat:
      return "unsupported-format";
    case ErrorCode::kCorruptStream:
      return "corrupt-stream";
    case ErrorCode::kTruncatedStream:
      return "truncated-stream";
    case ErrorCode::kUnsupportedVersion:
      return "unsupported-version";
    case ErrorCode::kChecksumMismatch:
      return "checksum-mismatch";
    case ErrorCode::kEmptyMesh:
      return "empty-mesh";
    case ErrorCode::kResourceLimit:
      return "resource-limit";
    case ErrorCode::kInternal:
      return "internal";
  }
  return "unknown";
}

}  // namespace pm
