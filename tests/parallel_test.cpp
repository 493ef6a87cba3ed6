// core/parallel.hpp: every index runs exactly once, a worker's exception reaches the caller, and a
// thread the system refuses to start costs nothing but speed.
#include "core/parallel.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
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
  // An index that throws stops the rest: far fewer than all 100000 run after it. Each index takes
  // a millisecond, so that a thread preempted between claiming index 10 and throwing (a loaded CI
  // machine) cannot watch the others finish the loop meanwhile.
  std::atomic<int> ran{0};
  EXPECT_THROW(parallel_dynamic(100000,
                                [&](std::int64_t i) {
                                  ++ran;
                                  if (i == 10) throw std::bad_alloc();
                                  std::this_thread::sleep_for(std::chrono::milliseconds(1));
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
  // it), no thread can start (EAGAIN); a pool asked for 8 workers gets none, and every index still
  // runs once, on the caller, with no std::terminate.
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    if (::geteuid() == 0 && (::setgid(65534) != 0 || ::setuid(65534) != 0)) ::_exit(3);
    const rlimit one{1, 1};
    if (::setrlimit(RLIMIT_NPROC, &one) != 0) ::_exit(4);
    ThreadPool pool(8);
    if (pool.threads() != 1) ::_exit(5);
    std::vector<int> runs(1000, 0);
    pool.run(1000, [&](std::int64_t i) { ++runs[static_cast<std::size_t>(i)]; });
    ::_exit(std::all_of(runs.begin(), runs.end(), [](int r) { return r == 1; }) ? 0 : 6);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the child died of signal " << WTERMSIG(status);
  if (WEXITSTATUS(status) == 3) GTEST_SKIP() << "root without CAP_SETUID: the process limit cannot bind";
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

TEST(Parallel, NestedLoopsRunOnThePoolsThreadsOnly) {
  // Loops inside loops inside loops, as files, materials and texels nest: every index runs once,
  // and no more distinct threads take part than the pool holds (its workers and this thread).
  ThreadPool& pool = ThreadPool::shared();
  std::mutex mutex;
  std::set<std::thread::id> seen;
  std::atomic<int> leaves{0};
  pool.run(6, [&](std::int64_t) {
    pool.run(5, [&](std::int64_t) {
      parallel_dynamic(7, [&](std::int64_t) {
        ++leaves;
        const std::lock_guard lock(mutex);
        seen.insert(std::this_thread::get_id());
      });
    });
  });
  EXPECT_EQ(leaves.load(), 6 * 5 * 7);
  EXPECT_LE(static_cast<std::int64_t>(seen.size()), pool.threads());
}

TEST(Parallel, ManyShortNestedLoopsEndCleanly) {
  // A loop ends while other threads may still hold it (they picked it, then found nothing left):
  // thousands of tiny nested loops make that window likely. It must neither crash nor hang, and
  // every index runs once.
  std::atomic<long> leaves{0};
  // Idle workers woken for a tiny loop often find it already run by its caller.
  for (int k = 0; k < 50000; ++k) ThreadPool::shared().run(2, [&](std::int64_t) { ++leaves; });
  EXPECT_EQ(leaves.exchange(0), 100000L);
  parallel_dynamic(20000, [&](std::int64_t) {
    parallel_for(0, 3, [&](std::int64_t) { parallel_dynamic(2, [&](std::int64_t) { ++leaves; }); });
  });
  EXPECT_EQ(leaves.load(), 20000L * 3 * 2);
}

TEST(Parallel, ALoopLimitedToNThreadsNeverRunsMoreAtOnce) {
  std::atomic<int> running{0}, most{0};
  ThreadPool::shared().run(
      40,
      [&](std::int64_t) {
        const int now = ++running;
        for (int seen = most.load(); now > seen && !most.compare_exchange_weak(seen, now);) {
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        --running;
      },
      1);
  EXPECT_EQ(most.load(), 1);
}

}  // namespace
}  // namespace gltf_pbr
