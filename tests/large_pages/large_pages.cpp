// pmenc's and pmdec's operator new (apps/large_pages.cpp, linked into this binary as into
// them): a block of kLargeBlock bytes or more is advised onto huge pages (its mapping carries
// the kernel's "hg" flag in /proc/self/smaps), a smaller one is not, and the pages advised are
// exactly those that hold the block.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <sys/stat.h>

#include "large_pages.h"

namespace pm::cli {
namespace {

TEST(LargePages, PagesOfABlockAreThoseThatHoldIt) {
  constexpr std::size_t kPage = 4096;
  EXPECT_EQ(pages_of(0x10010, 8, kPage).begin, 0x10000u);
  EXPECT_EQ(pages_of(0x10010, 8, kPage).end, 0x11000u);
  // A block on page boundaries is its own pages.
  EXPECT_EQ(pages_of(0x10000, 0x3000, kPage).begin, 0x10000u);
  EXPECT_EQ(pages_of(0x10000, 0x3000, kPage).end, 0x13000u);
  // Two bytes across a boundary: both pages.
  EXPECT_EQ(pages_of(0x10fff, 2, kPage).begin, 0x10000u);
  EXPECT_EQ(pages_of(0x10fff, 2, kPage).end, 0x12000u);
  // One byte past a boundary reaches into the next page.
  EXPECT_EQ(pages_of(0x10010, 0x1000, kPage).end, 0x12000u);
  // Another page size.
  EXPECT_EQ(pages_of(0x12345, 0x10000, 0x10000).begin, 0x10000u);
  EXPECT_EQ(pages_of(0x12345, 0x10000, 0x10000).end, 0x30000u);
}

// The VmFlags of the mapping of /proc/self/smaps that holds address ("" if none does).
std::string flags_of_mapping_holding(const void* address) {
  std::ifstream smaps("/proc/self/smaps");
  const auto target = reinterpret_cast<std::uintptr_t>(address);
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    std::uintptr_t begin = 0, end = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> begin >> dash >> end && dash == '-') {
      inside = begin <= target && target < end;
    } else if (inside && line.rfind("VmFlags:", 0) == 0) {
      return line;
    }
  }
  return "";
}

bool has_huge_page_advice(const std::string& flags) {
  return flags.find(" hg") != std::string::npos;
}

TEST(LargePages, TheEnvironmentTurnsTheAdviceOffWithZeroOnly) {
  EXPECT_TRUE(huge_pages_wanted(nullptr));
  EXPECT_TRUE(huge_pages_wanted("1"));
  EXPECT_TRUE(huge_pages_wanted(""));
  EXPECT_TRUE(huge_pages_wanted("00"));
  EXPECT_FALSE(huge_pages_wanted("0"));
}

// Run twice by CMake: as it is, and with PM_HUGE_PAGES=0, where no block is advised.
TEST(LargePages, LargeBlocksAreAdvisedOntoHugePagesAndSmallOnesAreNot) {
  if (!replaces_operator_new())
    GTEST_SKIP() << "a sanitizer build (or a system without madvise) keeps its own operator new";
  const bool wanted = huge_pages_wanted(std::getenv("PM_HUGE_PAGES"));
  EXPECT_EQ(advises_large_blocks(), wanted);
  struct stat info {};
  if (stat("/sys/kernel/mm/transparent_hugepage", &info) != 0)
    GTEST_SKIP() << "this kernel has no transparent huge pages";
  // A megabyte is mapped on its own by malloc (above its first mmap threshold) and not advised.
  const auto small = std::make_unique<char[]>(std::size_t{1} << 20);
  const std::string small_flags = flags_of_mapping_holding(small.get());
  ASSERT_FALSE(small_flags.empty());
  EXPECT_FALSE(has_huge_page_advice(small_flags)) << small_flags;
  const auto large = std::make_unique<char[]>(kLargeBlock);
  const std::string large_flags = flags_of_mapping_holding(large.get());
  ASSERT_FALSE(large_flags.empty());
  EXPECT_EQ(has_huge_page_advice(large_flags), wanted) << large_flags;
  // Its last byte too: the whole block is advised, not only its first page.
  EXPECT_EQ(has_huge_page_advice(flags_of_mapping_holding(large.get() + kLargeBlock - 1)), wanted);
}

}  // namespace
}  // namespace pm::cli
