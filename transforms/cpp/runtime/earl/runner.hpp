// earl runtime: how components are run. Deterministic: step them in a fixed order in one
// thread. Threaded: one thread per component, each at its own period.
// Part of earl-m2t's C++ target; header-only, C++17.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <thread>

#include "earl/component.hpp"

namespace earl {

/// One thread per component, each calling updateHook() every period() (absolute deadlines,
/// no drift), or, for an event-driven component, whenever its ready() holds (looked at every
/// kPoll: the lock-free channels cannot wake a thread). Threads are created by start()
/// (initialisation); a cycle neither allocates nor locks: components only meet through the
/// lock-free channels of their links.
template <std::size_t N>
class ThreadedRunner {
 public:
  explicit ThreadedRunner(const std::array<Component*, N>& components) noexcept
      : components_(components) {}
  ThreadedRunner(const ThreadedRunner&) = delete;
  ThreadedRunner& operator=(const ThreadedRunner&) = delete;
  ~ThreadedRunner() { stop(); }

  void start() {
    if (running_.exchange(true)) return;
    for (std::size_t i = 0; i < N; ++i) {
      Component* c = components_[i];
      threads_[i] = std::thread([this, c] { loop(*c); });
    }
  }

  void stop() noexcept {
    if (!running_.exchange(false)) return;
    for (std::thread& t : threads_) {
      if (t.joinable()) t.join();
    }
  }

 private:
  static constexpr std::chrono::microseconds kPoll{100};

  void loop(Component& c) noexcept {
    c.startHook();
    auto next = std::chrono::steady_clock::now();
    while (running_.load(std::memory_order_relaxed)) {
      if (c.eventDriven()) {
        while (!c.ready(std::chrono::steady_clock::now())) {
          if (!running_.load(std::memory_order_relaxed)) break;
          std::this_thread::sleep_for(kPoll);
        }
        if (!running_.load(std::memory_order_relaxed)) break;
        c.updateHook();
        continue;
      }
      c.updateHook();
      next += c.period();
      std::this_thread::sleep_until(next);
    }
    c.stopHook();
  }

  std::array<Component*, N> components_;
  std::array<std::thread, N> threads_{};
  std::atomic<bool> running_{false};
};

}  // namespace earl
