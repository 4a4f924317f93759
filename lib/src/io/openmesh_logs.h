// OpenMesh writes warnings to its log streams (omerr, omlog, omout); the library never
// prints, so it turns them off while it calls OpenMesh, and back to how the caller left
// them when it is done: no process-wide side effect outlives a library call.
//
// Calls may run at once on several threads: the first to enter saves the streams' states
// and disables them, the last to leave restores them (a count under a mutex), so that
// overlapping calls cannot restore each other's "disabled". While a call runs, OpenMesh's
// streams are off for the whole process. OpenMesh 9 creates the streams lazily and without
// a lock; here they are only touched under the mutex.
#pragma once

namespace pm {

class QuietOpenMeshLogs {
 public:
  QuietOpenMeshLogs();
  ~QuietOpenMeshLogs();
  QuietOpenMeshLogs(const QuietOpenMeshLogs&) = delete;
  QuietOpenMeshLogs& operator=(const QuietOpenMeshLogs&) = delete;
};

}  // namespace pm
