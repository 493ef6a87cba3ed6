// Splits [begin, end) into contiguous chunks, one per hardware thread, and runs them in parallel.
#pragma once
#include <algorithm>
#include <cstdint>
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
  std::vector<std::jthread> workers;
  for (std::int64_t t = 1; t < threads; ++t)
    workers.emplace_back([&, t] {
      for (std::int64_t i = begin + count * t / threads, stop = begin + count * (t + 1) / threads; i < stop; ++i)
        body(i);
    });
  for (std::int64_t i = begin, stop = begin + count / threads; i < stop; ++i) body(i);
}

}  // namespace gltf_pbr
