// Transparent huge pages for large random-access arrays, the unused end of a shrunk one and
// the allocator's free memory given back to the system (see huge_pages.h).
#include "core/huge_pages.h"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace pm::detail {

void prefer_huge_pages(const void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHugePage = std::uintptr_t{1} << 21;
  // Below a few huge pages the TLB covers the array anyway.
  constexpr std::size_t kLeast = 4 * kHugePage;
  // A hint: an old kernel, or huge pages disabled, leaves the pages as they were.
  if (data == nullptr || bytes < kLeast) return;
  // Only the huge pages wholly inside [data, data + bytes): what lies before and after the
  // range (the allocator's records) is never touched. An error leaves the pages as they were.
  const auto start = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t begin = (start + kHugePage - 1) & ~(kHugePage - 1);
  const std::uintptr_t end = (start + bytes) & ~(kHugePage - 1);
  if (end > begin) (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

void release_pages(const void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_DONTNEED)
  static const long page_size = sysconf(_SC_PAGESIZE);  // a huge page in the range is split
  if (data == nullptr || page_size <= 0) return;
  // Only the pages wholly inside the range: what lies before and after it (the array's
  // elements kept, the allocator's records) is never touched. An error leaves them as they
  // were.
  const auto page = static_cast<std::uintptr_t>(page_size);
  const auto start = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t begin = (start + page - 1) & ~(page - 1);
  const std::uintptr_t end = (start + bytes) & ~(page - 1);
  if (end > begin) (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_DONTNEED);
#else
  (void)data;
  (void)bytes;
#endif
}

void return_free_memory() {
#if defined(__GLIBC__)
  (void)malloc_trim(0);
#endif
}

}  // namespace pm::detail
