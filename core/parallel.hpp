// The threads of a run: workers on every hardware thread (or as many as asked), the caller's among
// them. An exception in any worker (bad_alloc on a huge bake) reaches the caller, the first one
// thrown, after every worker has stopped; it never terminates the process from a worker thread.
// A thread the system will not start (EAGAIN under a process limit) leaves its share of the work to
// the others instead of ending the process.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace gltf_pbr {

inline std::int64_t hardware_threads() { return std::max(1u, std::thread::hardware_concurrency()); }

// Runs worker() on `threads` threads at once, this one included, and returns when all are done.
// Each worker should take its work from a shared counter, so fewer started threads lose nothing.
template <typename Worker>
void run_on_threads(std::int64_t threads, const Worker& worker) {
  std::exception_ptr first_error;
  std::mutex error_mutex;
  auto guarded = [&] {
    try {
      worker();
    } catch (...) {
      const std::lock_guard lock(error_mutex);
      if (!first_error) first_error = std::current_exception();
    }
  };
  {
    std::vector<std::jthread> workers;
    workers.reserve(static_cast<std::size_t>(std::max<std::int64_t>(0, threads - 1)));
    for (std::int64_t t = 1; t < threads; ++t) {
      try {
        workers.emplace_back(guarded);
      } catch (const std::system_error&) {
        break;  // the ones started, and this thread, do the rest
      }
    }
    guarded();
  }  // joined
  if (first_error) std::rethrow_exception(first_error);
}

// body(i) for i in [begin, end) in contiguous chunks, one per hardware thread.
template <typename Body>  // Body: void(std::int64_t index)
void parallel_for(std::int64_t begin, std::int64_t end, const Body& body) {
  const std::int64_t count = end - begin;
  const std::int64_t chunks = std::min(hardware_threads(), count);
  if (chunks <= 1) {
    for (std::int64_t i = begin; i < end; ++i) body(i);
    return;
  }
  std::atomic<std::int64_t> next_chunk{0};
  std::atomic<bool> failed{false};  // once one index throws, the others stop at their next index
  run_on_threads(chunks, [&] {
    for (std::int64_t t; (t = next_chunk.fetch_add(1)) < chunks;)
      for (std::int64_t i = begin + count * t / chunks, stop = begin + count * (t + 1) / chunks;
           i < stop && !failed.load(std::memory_order_relaxed); ++i) {
        try {
          body(i);
        } catch (...) {
          failed = true;
          throw;
        }
      }
  });
}

// body(i) for i in [0, count) on every hardware thread, handing out indices one at a time (tiles
// and rows differ in cost, so a static split would leave cores idle).
template <typename Body>  // Body: void(std::int64_t index)
void parallel_dynamic(std::int64_t count, const Body& body) {
  std::atomic<std::int64_t> next{0};
  run_on_threads(std::min(hardware_threads(), count), [&] {
    for (std::int64_t i; (i = next.fetch_add(1)) < count;) {
      try {
        body(i);
      } catch (...) {
        next = count;  // the others take no further index
        throw;
      }
    }
  });
}

}  // namespace gltf_pbr
