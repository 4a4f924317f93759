// The global operator new of pmenc and pmdec: malloc, and for a block of kLargeBlock bytes or
// more, MADV_HUGEPAGE over its pages (large_pages.h says why). operator delete is free, so
// that the pair stays malloc's whichever of them a block meets.
#include "large_pages.h"

#include <cstdlib>
#include <new>
#include <string_view>

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || \
    __has_feature(memory_sanitizer)
#define PM_CLI_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define PM_CLI_SANITIZED 1
#endif
#if defined(__linux__) && !defined(PM_CLI_SANITIZED)
#define PM_CLI_ADVISE 1
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace pm::cli {

PageSpan pages_of(std::uintptr_t address, std::size_t size, std::size_t page) {
  const std::uintptr_t mask = page - 1;
  return {address & ~mask, (address + size + mask) & ~mask};
}

bool huge_pages_wanted(const char* value) {
  return value == nullptr || std::string_view(value) != "0";
}

#ifdef PM_CLI_ADVISE
bool replaces_operator_new() { return true; }

bool advises_large_blocks() {
  // Read once, on the first large block: getenv allocates nothing, so it may run here.
  static const bool wanted = huge_pages_wanted(std::getenv("PM_HUGE_PAGES"));
  return wanted;
}
#else
bool replaces_operator_new() { return false; }
bool advises_large_blocks() { return false; }
#endif

}  // namespace pm::cli

#ifdef PM_CLI_ADVISE
namespace {

void* allocate(std::size_t size) {
  void* block = nullptr;
  // As the standard's operator new: the new-handler, if any, is tried until it gives up.
  while ((block = std::malloc(size == 0 ? 1 : size)) == nullptr) {
    const std::new_handler handler = std::get_new_handler();
    if (handler == nullptr) throw std::bad_alloc();
    handler();
  }
  if (size >= pm::cli::kLargeBlock && pm::cli::advises_large_blocks()) {
    static const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
    const pm::cli::PageSpan span =
        pm::cli::pages_of(reinterpret_cast<std::uintptr_t>(block), size, page);
    // A hint: where the kernel has no huge pages it fails, and the block is as good.
    madvise(reinterpret_cast<void*>(span.begin), span.end - span.begin, MADV_HUGEPAGE);
  }
  return block;
}

}  // namespace

void* operator new(std::size_t size) { return allocate(size); }
void* operator new[](std::size_t size) { return allocate(size); }
void operator delete(void* block) noexcept { std::free(block); }
void operator delete[](void* block) noexcept { std::free(block); }
void operator delete(void* block, std::size_t) noexcept { std::free(block); }
void operator delete[](void* block, std::size_t) noexcept { std::free(block); }
#endif
