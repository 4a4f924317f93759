#include "io/openmesh_logs.h"

#include <OpenMesh/Core/System/omstream.hh>
#include <mutex>

namespace pm {
namespace {

struct Saved {
  std::mutex mutex;
  int active = 0;  // library calls inside a QuietOpenMeshLogs
  bool err = true, log = true, out = true;  // the states the first of them found
};

Saved& saved() {
  static Saved state;
  return state;
}

}  // namespace

QuietOpenMeshLogs::QuietOpenMeshLogs() {
  Saved& s = saved();
  std::lock_guard<std::mutex> lock(s.mutex);
  if (s.active++ > 0) return;
  s.err = omerr().is_enabled();
  s.log = omlog().is_enabled();
  s.out = omout().is_enabled();
  omerr().disable();
  omlog().disable();
  omout().disable();
}

QuietOpenMeshLogs::~QuietOpenMeshLogs() {
  Saved& s = saved();
  std::lock_guard<std::mutex> lock(s.mutex);
  if (--s.active > 0) return;
  if (s.err) omerr().enable();
  if (s.log) omlog().enable();
  if (s.out) omout().enable();
}

}  // namespace pm
