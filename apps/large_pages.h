// Large blocks on transparent huge pages, for pmenc's and pmdec's processes (not the
// library's business: how a process allocates is the program's choice, as glibc's
// glibc.malloc.hugetlb=1 tunable is the user's).
//
// Why: the tools' big arrays (the mesh, the collapse loop's state, the stream's buffers) are
// allocated, written through once or twice and freed, and the library gives free memory back
// between stages to keep the peak low (lib/src/core/memory_pages.h), so on 4 KiB pages each
// first touch of a block is a page fault, and a fault is dear on a virtual machine. Where the
// kernel makes huge pages only for memory that asks (its "madvise" mode, Debian's default),
// blocks of kLargeBlock bytes or more ask. The library asks for a few of its arrays itself,
// for the TLB (prefer_huge_pages() in lib/src/core/memory_pages.h: the same madvise over the
// inner huge pages of chosen arrays; internal to the library, so not called from here).
// Measured (tests/bench/page_faults.md, 2026-12-02, medians of 5 alternating runs on the
// 950,272-face textured mesh): pmenc --fast 8.83 -> 6.74 s, faults 195K -> 89K; pmenc 15.2 ->
// 11.6 s; pmdec of full detail 5.18 -> 3.24 s; peaks +1%, but pmdec --ratio 0.1 63 -> 70 MiB
// (a huge page is made whole at a block's growing end). Output bytes are the same.
#pragma once

#include <cstddef>
#include <cstdint>

namespace pm::cli {

// Blocks of at least this many bytes are advised (MADV_HUGEPAGE). Two huge pages: a smaller
// block holds at most one whole, and its tail may be faulted in for nothing.
inline constexpr std::size_t kLargeBlock = std::size_t{4} << 20;

// The pages [begin, end) that hold the block [address, address + size): begin rounded down
// and the end rounded up to `page` (a power of two). Advising a page the block shares with
// its neighbour is harmless: the advice changes when memory is made, never its contents.
struct PageSpan {
  std::uintptr_t begin, end;
};
PageSpan pages_of(std::uintptr_t address, std::size_t size, std::size_t page);

// Whether the environment variable PM_HUGE_PAGES, of this value (nullptr: unset), lets large
// blocks be advised: all but "0" do. The tools' man pages document it: a user whose system
// makes huge pages dear (memory that must stay small, a kernel that compacts for them) turns
// the advice off without rebuilding.
bool huge_pages_wanted(const char* value);

// Whether this program replaces operator new with the advising one: false in sanitizer
// builds, which keep their own, and where the system has no madvise.
bool replaces_operator_new();

// Whether large blocks are advised: the replacement is there and PM_HUGE_PAGES lets it.
bool advises_large_blocks();

}  // namespace pm::cli
