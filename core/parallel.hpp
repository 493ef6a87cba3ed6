// Splits [begin, end) into contiguous chunks, one per hardware thread, and runs them in parallel.
// An exception in any chunk (bad_alloc on a huge bake) reaches the caller, the first one thrown,
// after every chunk has stopped; it never terminates the process from a worker thread.
#pragma once
#include <algorithm>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace gltf_pbr {

template <typename Body>  // Body: void(std::int64_t index)
void parallel_for(std::int64_t begin, std::int64_t end, const Body& body) {
  const std::int64_t count = end - begin;
  const std::int64_t threads = std::min<std::int64_t>(std::max(1u, std::thread::hardware_concurrency()), count);
  if (threads <= 1) {
    for (std::int64_t i = begin; i < end; ++i) body(i);
    return;
  }
  std::exception_ptr first_error;
  std::mutex error_mutex;
  auto run_chunk = [&](std::int64_t t) {
    try {
      for (std::int64_t i = begin + count * t / threads, stop = begin + count * (t + 1) / threads; i < stop; ++i)
        body(i);
    } catch (...) {
      const std::lock_guard lock(error_mutex);
      if (!first_error) first_error = std::current_exception();
    }
  };
  {
    std::vector<std::jthread> workers;
    for (std::int64_t t = 1; t < threads; ++t) workers.emplace_back(run_chunk, t);
    run_chunk(0);
  }  // joined
  if (first_error) std::rethrow_exception(first_error);
}

}  // namespace gltf_pbr
