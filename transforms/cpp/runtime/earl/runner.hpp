// earl runtime: how components are run. Deterministic: step them in a fixed order in one
// thread. Threaded: one thread per component, each at its own period.
// Part of earl-m2t's C++ target; header-only, C++17.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <thread>

#include "earl/component.hpp"
#include "earl/realtime.hpp"
#include "earl/wake.hpp"

#ifndef EARL_WAKE_POLL
#define EARL_WAKE_POLL 0
#endif

namespace earl {

/// One thread per component, each calling updateHook() every period() (absolute deadlines,
/// no drift), or, for an event-driven component, whenever its ready() holds. Between two
/// iterations the thread sleeps on the component's wake word (earl/wake.hpp) until its next
/// deadline (Component::nextDeadline()), a value delivered into one of its inputs, or a
/// wake-up (a switch, stop()): no polling. Threads are created by start() (initialisation); a
/// cycle neither allocates nor locks: components only meet through the lock-free channels of
/// their links.
///
/// Bench-only: -DEARL_WAKE_POLL=1 builds the former loop instead, which looks at an
/// event-driven component's ready() every 100 us; bench/latency.py compares the two.
template <std::size_t N>
class ThreadedRunner {
 public:
  explicit ThreadedRunner(const std::array<Component*, N>& components) noexcept
      : components_(components) {}
  ThreadedRunner(const ThreadedRunner&) = delete;
  ThreadedRunner& operator=(const ThreadedRunner&) = delete;
  ~ThreadedRunner() { stop(); }

  /// Before start(): the real-time settings of the thread of ``components[index]``.
  void configure(std::size_t index, const ThreadSettings& settings) noexcept {
    if (index < N) settings_[index] = settings;
  }

  /// Starts every thread once each has taken its settings (earl/realtime.hpp). false when the
  /// system refused one: no component ran, and refusal() holds the line saying why.
  bool start() {
    if (running_.exchange(true)) return true;
    for (std::size_t i = 0; i < N; ++i) {
      threads_[i] = std::thread([this, i] { run(i); });
    }
    std::unique_lock<std::mutex> lock(startMutex_);
    startChanged_.wait(lock, [this] { return applied_ == N; });
    go_ = refused_ ? Go::abort : Go::run;
    lock.unlock();
    startChanged_.notify_all();
    if (go_ == Go::run) return true;
    running_.store(false);
    for (std::thread& t : threads_) {
      if (t.joinable()) t.join();
    }
    return false;
  }

  const char* refusal() const noexcept { return refusal_; }

  void stop() noexcept {
    if (!running_.exchange(false)) return;
    for (Component* c : components_) c->wake().notify();
    for (std::thread& t : threads_) {
      if (t.joinable()) t.join();
    }
  }

 private:
  enum class Go : std::uint8_t { wait, run, abort };

  /// A thread: its settings, then (once every thread has taken its own) the loop.
  void run(std::size_t index) noexcept {
    char message[sizeof refusal_];
    const bool applied = applyThreadSettings(settings_[index], components_[index]->name(), message, sizeof message);
    std::unique_lock<std::mutex> lock(startMutex_);
    if (!applied && !refused_) {
      refused_ = true;
      std::memcpy(refusal_, message, sizeof refusal_);
    }
    ++applied_;
    startChanged_.notify_all();
    startChanged_.wait(lock, [this] { return go_ != Go::wait; });
    if (go_ != Go::run) return;
    lock.unlock();
    loop(*components_[index]);
  }

#if EARL_WAKE_POLL
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
#else
  void loop(Component& c) noexcept {
    using Clock = Component::Clock;
    c.startHook();
    Wake& wake = c.wake();
    Clock::time_point next = Clock::now();
    while (running_.load(std::memory_order_seq_cst)) {
      if (c.eventDriven()) {
        // arm before looking: a value delivered after ready() said no ends the sleep at once
        const std::uint32_t armed = wake.arm();
        if (!running_.load(std::memory_order_seq_cst)) break;
        const Clock::time_point now = Clock::now();
        if (c.ready(now)) {
          c.updateHook();
          continue;
        }
        bool onData = false;
        const Clock::time_point deadline = c.nextDeadline(now, onData);
        if (deadline > now) wake.wait(armed, deadline, onData);
        continue;
      }
      c.updateHook();
      next += c.period();
      // values delivered meanwhile wait for the period; only stop() ends the sleep early
      for (Clock::time_point now = Clock::now(); now < next; now = Clock::now()) {
        const std::uint32_t armed = wake.arm();
        if (!running_.load(std::memory_order_seq_cst)) break;
        wake.wait(armed, next, false);
      }
    }
    c.stopHook();
  }
#endif

  std::array<Component*, N> components_;
  std::array<std::thread, N> threads_{};
  std::atomic<bool> running_{false};
  std::array<ThreadSettings, N> settings_{};
  // start-up only (never in a cycle): every thread reports its settings before any runs
  std::mutex startMutex_;
  std::condition_variable startChanged_;
  std::size_t applied_ = 0;
  bool refused_ = false;
  Go go_ = Go::wait;
  char refusal_[256] = {};
};

}  // namespace earl
