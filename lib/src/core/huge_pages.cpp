// Transparent huge pages for large random-access arrays, and giving back the unused end of a
// shrunk one (see huge_pages.h).
#include "core/huge_pages.h"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace pm::detail {

void prefer_huge_pages(const void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHugePage = std::uintptr_t{1} << 21;
  // Below a few huge pages the TLB covers the array anyway.
  constexpr std::size_t kLeast = 4 * kHugePage;
  if (data == nullptr || bytes < kLeast) return;
  const auto start = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t begin = (start + kHugePage - 1) & ~(kHugePage - 1);
  const std::uintptr_t end = (start + bytes) & ~(kHugePage - 1);
  if (end <= begin) return;
  // A hint: an error (an old kernel, huge pages disabled) leaves the pages as they were.
  (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

void release_pages(const void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_DONTNEED)
  static const long page_size = sysconf(_SC_PAGESIZE);  // a huge page in the range is split
  if (data == nullptr || page_size <= 0) return;
  const auto page = static_cast<std::uintptr_t>(page_size);
  const auto start = reinterpret_cast<std::uintptr_t>(data);
  // Only pages wholly inside the range: the allocator's records before and after it stay.
  const std::uintptr_t begin = (start + page - 1) & ~(page - 1);
  const std::uintptr_t end = (start + bytes) & ~(page - 1);
  if (end <= begin) return;
  // An error leaves the pages held, as they were: only the memory is not given back.
  (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_DONTNEED);
#else
  (void)data;
  (void)bytes;
#endif
}

}  // namespace pm::detail
