// Transparent huge pages for large random-access arrays, the unused end of a shrunk one and
// the allocator's free memory given back to the system (see memory_pages.h).
#include "core/memory_pages.h"

#include <cstdint>
#include <mutex>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace pm::detail {

#if defined(__linux__)
namespace {

// madvise(advice) over the pages of `page` bytes wholly inside [data, data + bytes): what
// lies before and after the range (an array's elements kept, the allocator's records) is
// never touched. An error leaves the pages as they were.
void advise_inner_pages(const void* data, std::size_t bytes, std::uintptr_t page, int advice) {
  const auto start = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t begin = (start + page - 1) & ~(page - 1);
  const std::uintptr_t end = (start + bytes) & ~(page - 1);
  if (end > begin) (void)madvise(reinterpret_cast<void*>(begin), end - begin, advice);
}

}  // namespace
#endif

void prefer_huge_pages(const void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHugePage = std::uintptr_t{1} << 21;
  // Below a few huge pages the TLB covers the array anyway.
  constexpr std::size_t kLeast = 4 * kHugePage;
  // A hint: an old kernel, or huge pages disabled, leaves the pages as they were.
  if (data == nullptr || bytes < kLeast) return;
  advise_inner_pages(data, bytes, kHugePage, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

void release_pages(const void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_DONTNEED)
  static const long page_size = sysconf(_SC_PAGESIZE);  // a huge page in the range is split
  if (data == nullptr || page_size <= 0) return;
  advise_inner_pages(data, bytes, static_cast<std::uintptr_t>(page_size), MADV_DONTNEED);
#else
  (void)data;
  (void)bytes;
#endif
}

void return_free_memory() {
#if defined(__GLIBC__)
  // One call at a time. Where malloc is not glibc's (a sanitizer's, or an allocator loaded
  // before glibc's), no malloc has set glibc's arenas up, malloc_trim() does it itself, and
  // two threads doing so at once crash (AddressSanitizer, pmenc's batch on two jobs: a read
  // at 0x8 in mtrim). Once they are set up, calls at once are safe, and this lock costs a
  // batch nothing: one call per encode.
  static std::mutex one_at_a_time;
  const std::lock_guard<std::mutex> lock(one_at_a_time);
  (void)malloc_trim(0);
#endif
}

}  // namespace pm::detail
