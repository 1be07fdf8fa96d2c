// earl runtime: how components are run. Deterministic: step them in a fixed order in one
// thread. Threaded: a thread per event-driven component, and a thread per period for the
// periodic ones (or one per component, ThreadPlan::perSubsystem).
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

/// An event-driven component has a thread of its own, which calls updateHook() whenever its
/// ready() holds. Periodic components of the same period and the same real-time settings share
/// one thread (ThreadPlan::perPeriod, the default), which calls updateHook() of each, in the
/// order given, every period (absolute deadlines, no drift): one wake-up per period instead of
/// one per component. ThreadPlan::perSubsystem gives every component a thread of its own.
/// Between two iterations a thread sleeps on a wake word (earl/wake.hpp) until its next
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

  /// Before start(): whether periodic components share a thread per period (the default).
  void plan(ThreadPlan plan) noexcept { plan_ = plan; }

  /// After start(): how many threads run the components.
  std::size_t threads() const noexcept { return groups_; }

  /// Starts every thread once each has taken its settings (earl/realtime.hpp). false when the
  /// system refused one: no component ran, and refusal() holds the line saying why.
  bool start() {
    if (running_.exchange(true)) return true;
    group();
    for (std::size_t g = 0; g < groups_; ++g) {
      threads_[g] = std::thread([this, g] { run(g); });
    }
    std::unique_lock<std::mutex> lock(startMutex_);
    startChanged_.wait(lock, [this] { return applied_ == groups_; });
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

  /// The threads: ``order_`` lists the components thread by thread, thread g running
  /// order_[first_[g]] .. order_[first_[g + 1] - 1], in the order the components were given.
  void group() noexcept {
    std::array<bool, N> placed{};
    groups_ = 0;
    std::size_t next = 0;
    for (std::size_t i = 0; i < N; ++i) {
      if (placed[i]) continue;
      first_[groups_++] = next;
      order_[next++] = i;
      placed[i] = true;
      if (plan_ == ThreadPlan::perSubsystem || components_[i]->eventDriven()) continue;
      for (std::size_t j = i + 1; j < N; ++j) {
        if (placed[j] || components_[j]->eventDriven() || components_[j]->period() != components_[i]->period() ||
            !sameSettings(settings_[j], settings_[i])) {
          continue;
        }
        order_[next++] = j;
        placed[j] = true;
      }
    }
    first_[groups_] = next;
  }

  static bool sameSettings(const ThreadSettings& a, const ThreadSettings& b) noexcept {
    return a.priority == b.priority && a.cpu == b.cpu;
  }

  /// A thread: its settings, then (once every thread has taken its own) the loop.
  void run(std::size_t g) noexcept {
    const std::size_t index = order_[first_[g]];
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
    Component& c = *components_[index];
    if (c.eventDriven()) {
      loop(c);
    } else {
      loopPeriodic(first_[g], first_[g + 1]);
    }
  }

#if EARL_WAKE_POLL
  static constexpr std::chrono::microseconds kPoll{100};

  void loop(Component& c) noexcept {
    c.startHook();
    while (running_.load(std::memory_order_relaxed)) {
      while (!c.ready(std::chrono::steady_clock::now())) {
        if (!running_.load(std::memory_order_relaxed)) break;
        std::this_thread::sleep_for(kPoll);
      }
      if (!running_.load(std::memory_order_relaxed)) break;
      c.updateHook();
    }
    c.stopHook();
  }

  void loopPeriodic(std::size_t begin, std::size_t end) noexcept {
    for (std::size_t k = begin; k < end; ++k) components_[order_[k]]->startHook();
    auto next = std::chrono::steady_clock::now();
    while (running_.load(std::memory_order_relaxed)) {
      for (std::size_t k = begin; k < end; ++k) components_[order_[k]]->updateHook();
      next += components_[order_[begin]]->period();
      std::this_thread::sleep_until(next);
    }
    for (std::size_t k = begin; k < end; ++k) components_[order_[k]]->stopHook();
  }
#else
  /// An event-driven component's thread.
  void loop(Component& c) noexcept {
    using Clock = Component::Clock;
    c.startHook();
    Wake& wake = c.wake();
    while (running_.load(std::memory_order_seq_cst)) {
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
      if (deadline > now) wake.wait(armed, deadline, onData ? c.wakeInputs() : std::uint64_t{0});
    }
    c.stopHook();
  }

  /// The thread of the periodic components order_[begin] .. order_[end - 1], one period.
  void loopPeriodic(std::size_t begin, std::size_t end) noexcept {
    using Clock = Component::Clock;
    for (std::size_t k = begin; k < end; ++k) components_[order_[k]]->startHook();
    // stop() wakes every component's word, so the first one's is enough to sleep on
    Wake& wake = components_[order_[begin]]->wake();
    const Clock::duration period = components_[order_[begin]]->period();
    Clock::time_point next = Clock::now();
    while (running_.load(std::memory_order_seq_cst)) {
      for (std::size_t k = begin; k < end; ++k) components_[order_[k]]->updateHook();
      next += period;
      // values delivered meanwhile wait for the period; only stop() ends the sleep early
      for (Clock::time_point now = Clock::now(); now < next; now = Clock::now()) {
        const std::uint32_t armed = wake.arm();
        if (!running_.load(std::memory_order_seq_cst)) break;
        wake.wait(armed, next, false);
      }
    }
    for (std::size_t k = begin; k < end; ++k) components_[order_[k]]->stopHook();
  }
#endif

  std::array<Component*, N> components_;
  std::array<std::thread, N> threads_{};
  std::atomic<bool> running_{false};
  std::array<ThreadSettings, N> settings_{};
  ThreadPlan plan_ = ThreadPlan::perPeriod;
  std::array<std::size_t, N> order_{};
  std::array<std::size_t, N + 1> first_{};
  std::size_t groups_ = 0;
  // start-up only (never in a cycle): every thread reports its settings before any runs
  std::mutex startMutex_;
  std::condition_variable startChanged_;
  std::size_t applied_ = 0;
  bool refused_ = false;
  Go go_ = Go::wait;
  char refusal_[256] = {};
};

}  // namespace earl
