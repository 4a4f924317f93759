// Threads refused: this binary replaces pthread_create, so that the library's thread starts
// fail on demand (EAGAIN, as under a process or thread limit), and is a binary of its own: the
// suite's other tests must not run under it. Whatever starts are refused, encode() and
// write_pm() give the stream they give with every thread (the work goes to the threads that
// did start, or the caller's), never an exception (status.h) or an abort (a std::thread left
// joinable). Found by review: run_in_turn() let std::system_error out of encode(), or, when a
// later helper was refused, aborted with the first one still running.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <pthread.h>

#include <atomic>
#include <cerrno>
#include <string>

#include "pm/encoder.h"
#include "pm/pm_codec.h"
#include "test_util.h"

namespace {

// Thread starts allowed before every later one is refused; negative: no limit.
std::atomic<int> starts_left{-1};
std::atomic<int> refused{0};

}  // namespace

extern "C" int pthread_create(pthread_t* thread, const pthread_attr_t* attr,
                              void* (*start)(void*), void* arg) {
  using Create = int (*)(pthread_t*, const pthread_attr_t*, void* (*)(void*), void*);
  static const Create real = reinterpret_cast<Create>(dlsym(RTLD_NEXT, "pthread_create"));
  if (starts_left.load() >= 0 && starts_left.fetch_sub(1) <= 0) {
    starts_left = 0;
    ++refused;
    return EAGAIN;
  }
  return real(thread, attr, start, arg);
}

namespace pm {
namespace {

// Large enough for the loop's regions (rounds of four and two regions on two threads and
// more) and the attributes' two kinds on two threads.
Mesh grid_with_attributes() { return test::seamed_grid(128); }

std::string encoded(const Mesh& mesh, unsigned threads, int allowed) {
  EncodeOptions options;
  options.threads = threads;
  options.fast_partition_vertices = 256;
  WriteOptions write;
  write.threads = threads;
  starts_left = allowed;
  refused = 0;
  std::string bytes;
  Status status;
  try {
    ProgressiveMesh pm;
    status = encode(mesh, options, pm);
    if (status) status = write_pm(pm, write, bytes);
  } catch (const std::exception& e) {
    starts_left = -1;
    ADD_FAILURE() << "an exception left the library: " << e.what();
    return {};
  }
  starts_left = -1;
  EXPECT_TRUE(status.is_ok()) << status.message();
  return bytes;
}

TEST(ThreadRefusal, EveryStartRefusedGivesTheSameStream) {
  const Mesh mesh = grid_with_attributes();
  const std::string reference = encoded(mesh, 1, -1);
  ASSERT_FALSE(reference.empty());
  const std::string refused_all = encoded(mesh, 4, 0);
  EXPECT_GT(refused.load(), 0) << "no start was refused: the test tests nothing";
  EXPECT_TRUE(refused_all == reference) << "the streams differ";
}

TEST(ThreadRefusal, LaterStartsRefusedGiveTheSameStream) {
  const Mesh mesh = grid_with_attributes();
  const std::string reference = encoded(mesh, 1, -1);
  ASSERT_FALSE(reference.empty());
  for (int allowed : {1, 2, 3, 5}) {
    SCOPED_TRACE("starts allowed: " + std::to_string(allowed));
    const std::string bytes = encoded(mesh, 4, allowed);
    EXPECT_GT(refused.load(), 0) << "no start was refused";
    EXPECT_TRUE(bytes == reference) << "the streams differ";
  }
}

}  // namespace
}  // namespace pm
