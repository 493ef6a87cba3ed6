// The threads of the process: one pool of hardware_threads() - 1 workers, started on first use,
// plus whichever thread asks for work to be done. Files, materials, texels and pixels all run on
// it, nested as they come (a bake inside a file inside a batch), so `convert -j N` never holds more
// threads than the pool: nested loops share the same workers instead of each starting its own.
//
// An exception in any index (bad_alloc on a huge bake) reaches the caller, the first one thrown,
// after every index has stopped; no further index of that loop starts. A worker the system will not
// start (EAGAIN under a process limit) leaves its share to the others instead of ending the process.
#pragma once
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace gltf_pbr {

inline std::int64_t hardware_threads() { return std::max(1u, std::thread::hardware_concurrency()); }

class ThreadPool {
 public:
  // The process's pool.
  static ThreadPool& shared();

  // body(i) for every i in [0, count), each once, on the calling thread and any idle workers, at
  // most `max_threads` of them at a time (0: no limit). Returns when all have run; while it waits
  // the caller runs indices of loops started after this one (inside it, or by another thread since:
  // another bake's bands), never of older ones (a batch's next file does not pile up on a waiting
  // thread's stack).
  void run(std::int64_t count, const std::function<void(std::int64_t)>& body, std::int64_t max_threads = 0);

  // Workers started, plus one for the caller.
  std::int64_t threads() const { return static_cast<std::int64_t>(workers_.size()) + 1; }

  // A pool of its own with up to `workers` threads besides its callers (tests; everything else
  // runs on shared()).
  explicit ThreadPool(std::int64_t workers);
  ~ThreadPool();

 private:
  struct Loop;
  Loop* claimable(std::uint64_t newer_than);  // with the lock held
  bool run_one(Loop& loop);                   // claims and runs one index; false when none is left
  void help(Loop& loop);                      // runs its indices while any are left, then lets go of it
  void work();

  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<Loop*> loops_;  // loops with indices left to claim, oldest first
  std::uint64_t next_sequence_ = 0;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

// Runs worker() once on each of `threads` threads of the pool at once (the caller among them when
// the pool has fewer), and returns when all are done. Each worker should take its work from a
// shared counter.
template <typename Worker>
void run_on_threads(std::int64_t threads, const Worker& worker) {
  ThreadPool::shared().run(
      threads, [&](std::int64_t) { worker(); }, threads);
}

// body(i) for i in [begin, end) in contiguous chunks, one per thread of the pool.
template <typename Body>  // Body: void(std::int64_t index)
void parallel_for(std::int64_t begin, std::int64_t end, const Body& body) {
  const std::int64_t count = end - begin;
  const std::int64_t chunks = std::min(ThreadPool::shared().threads(), count);
  if (chunks <= 1) {
    for (std::int64_t i = begin; i < end; ++i) body(i);
    return;
  }
  ThreadPool::shared().run(chunks, [&](std::int64_t t) {
    for (std::int64_t i = begin + count * t / chunks, stop = begin + count * (t + 1) / chunks; i < stop; ++i) body(i);
  });
}

// body(i) for i in [0, count) on the pool, handing out indices one at a time (tiles and rows
// differ in cost, so a static split would leave cores idle).
template <typename Body>  // Body: void(std::int64_t index)
void parallel_dynamic(std::int64_t count, const Body& body) {
  ThreadPool::shared().run(count, [&](std::int64_t i) { body(i); });
}

// first() and second(), at once when a thread of the pool is free.
template <typename First, typename Second>
void parallel_invoke(const First& first, const Second& second) {
  ThreadPool::shared().run(2, [&](std::int64_t i) { i == 0 ? first() : second(); });
}

}  // namespace gltf_pbr
