// The pages under the library's large arrays, asked for and given back. Asked for: huge
// pages for the large arrays that are read at random; given back: the unused end of an array
// shrunk in place, and the allocator's free memory between stages.
//
// Transparent huge pages for the large arrays that are read at random: the connectivity a
// .pm stream is decoded against, the decoded positions, the faces a level is replayed on.
// Each split touches a few records scattered over tens of megabytes, and with 4 KiB pages
// nearly every one of those touches also misses the TLB (a few thousand entries cover a few
// MiB); a 2 MiB page covers 512 times as much. Linux gives such pages to a process's
// anonymous memory only where it is asked to (MADV_HUGEPAGE), when the system's setting is
// "madvise", Debian's default (Linux admin guide, "Transparent Hugepage Support").
//
// Only a hint: elsewhere, on small arrays, or when the kernel declines, nothing changes.
// It never changes a result. The collapse loop asks for its per-vertex, per-face and
// per-half-edge arrays too: each collapse reads a neighbourhood's records, and consecutive
// collapses are anywhere on the mesh (nefertiti after two Loop steps, one thread, without
// the measure: medians of alternating runs 2069 -> 2038 ms, minima 2042 -> 1967; the bunny
// after three, 5852 -> 5625 ms). And the other way: shrink_in_place(), for an array that
// shrinks (the collapse loop's, as its faces die), and return_free_memory() between stages.
// Internal to the library.
#pragma once

#include <cstddef>
#include <type_traits>
#include <vector>

namespace pm::detail {

// Asks for huge pages over the 2 MiB-aligned part of [data, data + bytes), when that part is
// large enough to matter. Best before the memory is first written: pages already touched
// stay small until the kernel's background collapsing gets to them.
void prefer_huge_pages(const void* data, std::size_t bytes);

// The same over a vector's whole capacity (call it after reserve()).
template <class T>
void prefer_huge_pages(const std::vector<T>& values) {
  prefer_huge_pages(values.data(), values.capacity() * sizeof(T));
}

// values = n copies of `value`, its memory asked for huge pages before it is first written
// (a new allocation when the old one is too small). The vector alone gives the type, so a
// plain 0 or {} fills any.
template <class T>
void assign_preferring_huge_pages(std::vector<T>& values, std::size_t n,
                                  const typename std::vector<T>::value_type& value) {
  if (values.capacity() < n) {
    std::vector<T>().swap(values);
    values.reserve(n);
    prefer_huge_pages(values);
  }
  values.assign(n, value);
}

// Gives the whole pages of [data, data + bytes) back to the system: their contents are lost
// (Linux's MADV_DONTNEED: they read as zeros if touched again, which the callers never do).
// For the unused end of a large array that shrank in place; elsewhere nothing happens.
void release_pages(const void* data, std::size_t bytes);

// values shrunk to its first n elements in place, the memory of the rest given back
// (release_pages()): shrink_to_fit() would copy the n elements to a new array, held beside
// the old one for the copy's length, where the point of shrinking is to lower the peak.
template <class T>
void shrink_in_place(std::vector<T>& values, std::size_t n) {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>,
                "the released elements are never destroyed or read");
  if (n >= values.size()) return;
  values.resize(n);
  release_pages(values.data() + n, (values.capacity() - n) * sizeof(T));
}

// Gives the allocator's free memory back to the system (glibc: malloc_trim; elsewhere nothing),
// safe on any number of threads at once (the calls take turns).
// After a stage whose arrays go all at once: glibc keeps the freed memory of mid-sized
// arrays for reuse, but the next stage's arrays, of other sizes, do not fit in its pieces and
// come on top. pmenc --fast on the 950K-face textured mesh: after the collapse loop's state
// goes, the resident set 178 -> 105 MiB, and layer_splits' peak 244 -> 197 (encode.cpp).
void return_free_memory();

}  // namespace pm::detail
