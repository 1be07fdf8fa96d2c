// earl runtime: a component's wake word. The threaded runner sleeps a component's thread on it
// until the earliest of: a value delivered into one of its inputs, its next deadline (timeout,
// minimal period, period), or an explicit wake-up (a switch changing its agent's phase, stop()).
// Part of earl-m2t's C++ target; header-only, C++17, Linux (futex).
//
// The word is a sequence number that every delivery increments. A sleeper reads it (arm()),
// checks whether it may run, and sleeps only while the word still holds what it read: a value
// delivered in between makes the futex call return at once, so no wake-up is lost. A writer
// makes a system call only when the reader is asleep waiting for data into that input (each
// input is one bit of a mask; the reader names the inputs that can make it ready, the
// obligatory ones of its state); otherwise a delivery is one atomic increment and two loads,
// lock-free, no allocation.
#pragma once

#include <atomic>
#include <chrono>
#include <climits>
#include <cstddef>
#include <cstdint>
#include <ctime>

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace earl {

class Wake {
 public:
  using Clock = std::chrono::steady_clock;

  Wake() noexcept = default;
  Wake(const Wake&) = delete;
  Wake& operator=(const Wake&) = delete;

  /// Every input: the mask of an input that has no bit of its own, or of a sleeper that any
  /// delivery wakes. Inputs are numbered from 0; the 64th and later share bit 63.
  static constexpr std::uint64_t kAnyInput = ~std::uint64_t{0};
  static constexpr std::uint64_t inputBit(std::size_t index) noexcept {
    return std::uint64_t{1} << (index < 63 ? index : 63);
  }

  /// The writer's side: a value was delivered into the reader's input(s) ``inputs``.
  void data(std::uint64_t inputs = kAnyInput) noexcept {
    seq_.fetch_add(1, std::memory_order_seq_cst);
    if (sleeping_.load(std::memory_order_seq_cst) == kOnData && (wanted_.load(std::memory_order_seq_cst) & inputs) != 0) {
      wakeAll();
    }
  }

  /// Wakes the reader whatever it waits for (its agent's phase changed, the runner stops).
  void notify() noexcept {
    seq_.fetch_add(1, std::memory_order_seq_cst);
    if (sleeping_.load(std::memory_order_seq_cst) != kAwake) wakeAll();
  }

  /// The reader's side, before it checks whether it may run: the word to pass to wait().
  std::uint32_t arm() const noexcept { return seq_.load(std::memory_order_seq_cst); }

  /// Sleeps until ``deadline`` (Clock::time_point::max(): none) or a wake-up after arm()
  /// returned ``armed``; ``onData``: a delivery wakes it too (otherwise only notify()).
  void wait(std::uint32_t armed, Clock::time_point deadline, bool onData) noexcept {
    wait(armed, deadline, onData ? kAnyInput : std::uint64_t{0});
  }

  /// The same, woken only by a delivery into one of ``inputs`` (0: none, only notify()). A
  /// delivery into another input does not wake it (it cannot make the reader ready).
  void wait(std::uint32_t armed, Clock::time_point deadline, std::uint64_t inputs) noexcept {
    wanted_.store(inputs, std::memory_order_seq_cst);
    sleeping_.store(inputs != 0 ? kOnData : kForced, std::memory_order_seq_cst);
    if (seq_.load(std::memory_order_seq_cst) == armed) {
      timespec at{};
      const timespec* timeout = nullptr;
      if (deadline != Clock::time_point::max()) {
        // steady_clock is CLOCK_MONOTONIC, which FUTEX_WAIT_BITSET's absolute deadline uses
        const std::int64_t ns =
            std::chrono::duration_cast<std::chrono::nanoseconds>(deadline.time_since_epoch()).count();
        at.tv_sec = static_cast<time_t>(ns < 0 ? 0 : ns / 1'000'000'000);
        at.tv_nsec = static_cast<long>(ns < 0 ? 0 : ns % 1'000'000'000);
        timeout = &at;
      }
      syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&seq_), FUTEX_WAIT_BITSET | FUTEX_PRIVATE_FLAG, armed,
              timeout, nullptr, FUTEX_BITSET_MATCH_ANY);
    }
    sleeping_.store(kAwake, std::memory_order_seq_cst);
  }

  /// Deliveries and wake-ups so far (tests).
  std::uint32_t sequence() const noexcept { return arm(); }

 private:
  static constexpr std::uint32_t kAwake = 0;
  static constexpr std::uint32_t kOnData = 1;  // asleep; a delivery wakes it
  static constexpr std::uint32_t kForced = 2;  // asleep until its deadline or notify()

  void wakeAll() noexcept {
    syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&seq_), FUTEX_WAKE | FUTEX_PRIVATE_FLAG, INT_MAX, nullptr,
            nullptr, 0);
  }

  static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t), "a futex word is 32 bits");
  std::atomic<std::uint32_t> seq_{0};
  std::atomic<std::uint32_t> sleeping_{kAwake};
  std::atomic<std::uint64_t> wanted_{kAnyInput};  // the inputs whose delivery wakes the sleeper
};

}  // namespace earl
