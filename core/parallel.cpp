// The process's thread pool (see parallel.hpp).
#include "core/parallel.hpp"

#include <memory>
#include <system_error>

namespace gltf_pbr {

struct ThreadPool::Loop {
  std::int64_t count = 0, max_threads = 0;
  const std::function<void(std::int64_t)>* body = nullptr;
  std::uint64_t sequence = 0;  // loops started later have larger numbers
  std::atomic<std::int64_t> next{0}, finished{0}, running{0};
  std::atomic<bool> failed{false};
  int helpers = 0;  // other threads holding this loop, guarded by the pool's mutex: it lives until 0
  std::mutex error_mutex;
  std::exception_ptr error;
  bool claimable() const {
    return next.load(std::memory_order_relaxed) < count &&
           (max_threads <= 0 || running.load(std::memory_order_relaxed) < max_threads);
  }
};

ThreadPool& ThreadPool::shared() {
  static ThreadPool pool(hardware_threads() - 1);
  return pool;
}

ThreadPool::ThreadPool(std::int64_t workers) {
  for (std::int64_t w = 0; w < workers; ++w) {
    try {
      workers_.emplace_back([this] { work(); });
    } catch (const std::system_error&) {
      break;  // the ones started, and the callers, do the work
    }
  }
}

ThreadPool::~ThreadPool() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

ThreadPool::Loop* ThreadPool::claimable(std::uint64_t newer_than) {
  for (Loop* loop : loops_)
    if (loop->sequence > newer_than && loop->claimable()) return loop;
  return nullptr;
}

bool ThreadPool::run_one(Loop& loop) {
  if (loop.max_threads > 0 && loop.running.fetch_add(1) >= loop.max_threads) {
    loop.running.fetch_sub(1);
    return false;
  }
  const std::int64_t i = loop.next.fetch_add(1);
  if (i < loop.count) {
    if (!loop.failed.load(std::memory_order_relaxed)) {
      try {
        (*loop.body)(i);
      } catch (...) {
        const std::lock_guard lock(loop.error_mutex);
        if (!loop.error) loop.error = std::current_exception();
        loop.failed = true;
      }
    }
  }
  if (loop.max_threads > 0) loop.running.fetch_sub(1);
  if (i >= loop.count) return false;
  // The last index wakes the loop's owner; under the lock, so the wake-up cannot be lost.
  if (loop.finished.fetch_add(1) + 1 == loop.count) {
    const std::lock_guard lock(mutex_);
    changed_.notify_all();
  }
  return true;
}

void ThreadPool::help(Loop& loop) {
  while (run_one(loop)) {
  }
  const std::lock_guard lock(mutex_);
  if (--loop.helpers == 0) changed_.notify_all();  // its owner may be waiting to return
}

void ThreadPool::work() {
  for (;;) {
    Loop* loop = nullptr;
    {
      std::unique_lock lock(mutex_);
      changed_.wait(lock, [&] { return stopping_ || (loop = claimable(0)) != nullptr; });
      if (!loop) return;  // stopping, nothing left
      ++loop->helpers;
    }
    help(*loop);
  }
}

void ThreadPool::run(std::int64_t count, const std::function<void(std::int64_t)>& body, std::int64_t max_threads) {
  if (count <= 0) return;
  if (count == 1 || workers_.empty()) {  // nothing to share: run here, as the loop would
    for (std::int64_t i = 0; i < count; ++i) body(i);
    return;
  }
  // On the heap, not this stack: a thread that outlived the loop would be a use after free that
  // AddressSanitizer reports (tests/parallel_test.cpp stresses it).
  const auto owned = std::make_unique<Loop>();
  Loop& loop = *owned;
  loop.count = count;
  loop.max_threads = max_threads;
  loop.body = &body;
  {
    const std::lock_guard lock(mutex_);
    loop.sequence = ++next_sequence_;
    loops_.push_back(&loop);
  }
  changed_.notify_all();
  while (run_one(loop)) {
  }
  // The rest run on other threads; meanwhile help with loops started inside them (never an older,
  // unrelated one), and sleep when there are none.
  // The loop lives on this stack: it is unlisted, and this returns, only when every index has run
  // and no other thread still holds it.
  for (;;) {
    Loop* other = nullptr;
    {
      std::unique_lock lock(mutex_);
      const auto done = [&] { return loop.finished.load() == count && loop.helpers == 0; };
      changed_.wait(lock, [&] { return done() || (other = claimable(loop.sequence)) != nullptr || loop.claimable(); });
      if (done()) {
        loops_.erase(std::find(loops_.begin(), loops_.end(), &loop));
        break;
      }
      if (other) ++other->helpers;
    }
    if (other) {
      help(*other);
    } else {
      while (run_one(loop)) {
      }
    }
  }
  if (loop.error) std::rethrow_exception(loop.error);
}

}  // namespace gltf_pbr
