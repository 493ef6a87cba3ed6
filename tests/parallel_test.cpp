// core/parallel.hpp: every index runs exactly once, a worker's exception reaches the caller, and a
// thread the system refuses to start costs nothing but speed.
#include "core/parallel.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

namespace gltf_pbr {
namespace {

// Every index of [0, count) once: the sum of distinct weights says which ran and how often.
bool each_index_once(std::int64_t count, bool dynamic) {
  std::vector<std::atomic<int>> runs(static_cast<std::size_t>(count));
  auto body = [&](std::int64_t i) { runs[static_cast<std::size_t>(i)]++; };
  if (dynamic)
    parallel_dynamic(count, body);
  else
    parallel_for(0, count, body);
  for (const auto& r : runs)
    if (r != 1) return false;
  return true;
}

TEST(Parallel, EveryIndexRunsExactlyOnce) {
  for (std::int64_t count : {0, 1, 2, 3, 17, 1000}) {
    EXPECT_TRUE(each_index_once(count, false)) << count;
    EXPECT_TRUE(each_index_once(count, true)) << count;
  }
}

TEST(Parallel, AWorkersExceptionReachesTheCallerAfterAllStopped) {
  // Every worker sleeps before it finishes; one throws. When the exception arrives, each worker
  // that started has finished: none is still running on the caller's stack.
  std::atomic<int> started{0}, finished{0};
  try {
    run_on_threads(4, [&] {
      const int me = started++;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      ++finished;
      if (me == 0) throw std::runtime_error("one worker failed");
    });
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error&) {
    EXPECT_EQ(finished.load(), started.load());
  }
  // An index that throws stops the rest: far fewer than all 100000 run after it.
  std::atomic<int> ran{0};
  EXPECT_THROW(parallel_dynamic(100000,
                                [&](std::int64_t i) {
                                  ++ran;
                                  if (i == 10) throw std::bad_alloc();
                                }),
               std::bad_alloc);
  EXPECT_LT(ran.load(), 1000);
  EXPECT_THROW(parallel_for(0, 100,
                            [](std::int64_t i) {
                              if (i == 57) throw std::bad_alloc();
                            }),
               std::bad_alloc);
}

TEST(Parallel, ThreadsTheSystemWillNotStartLeaveTheirWorkToTheOthers) {
  // In a child: as a user limited to one process (root gives up root first, as limits do not bind
  // it), no thread can start (EAGAIN); every index must still run, with no std::terminate.
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    if (::geteuid() == 0 && (::setgid(65534) != 0 || ::setuid(65534) != 0)) ::_exit(3);
    const rlimit one{1, 1};
    if (::setrlimit(RLIMIT_NPROC, &one) != 0) ::_exit(4);
    std::atomic<int> ran{0};
    run_on_threads(8, [&] { ++ran; });
    const bool all = each_index_once(1000, false) && each_index_once(1000, true);
    ::_exit(ran == 1 && all ? 0 : 5);  // ran: only this thread started
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the child died of signal " << WTERMSIG(status);
  if (WEXITSTATUS(status) == 3) GTEST_SKIP() << "root without CAP_SETUID: the process limit cannot bind";
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

}  // namespace
}  // namespace gltf_pbr
