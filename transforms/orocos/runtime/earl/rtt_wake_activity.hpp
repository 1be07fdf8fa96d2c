// earl runtime for Orocos RTT 2.x: the activity of an event-driven master component. Part of
// earl-m2t's Orocos target (docs/orocos-target.md, Activation); header-only, C++17, Linux.
//
// A non-periodic RTT::Activity (its own thread, scheduler, priority and CPU affinity, stopped
// and started as any other) whose thread sleeps on an earl::Wake word (a futex) until the
// earliest of: trigger() (data on an event port, a message for the component's engine),
// timeout() (TaskCore::trigger(): an update step), breakLoop() (stop), or the deadline the
// component last set with wakeAt() (the subsystem's next deadline: minimal period, timeout).
// trigger() and timeout() are one atomic store and Wake::notify(), which makes a system call
// only when the thread sleeps: no lock, no allocation, no pipe. The thread steps the
// component's ExecutionEngine as RTT's FileDescriptorActivity does: work(Trigger) for a
// trigger (messages and port callbacks), work(TimeOut) for a timeout or a deadline passed
// (also updateHook()). A deadline passed is cleared before that step; the component sets the
// next one in its updateHook() (none: Clock::time_point::max()).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>

#include <rtt/Activity.hpp>
#include <rtt/base/RunnableInterface.hpp>

#include "earl/wake.hpp"

namespace earl::rtt {

class WakeActivity final : public RTT::Activity {
 public:
  using Clock = earl::Wake::Clock;

  WakeActivity(int scheduler, int priority, unsigned cpuAffinity, const std::string& name)
      : RTT::Activity(scheduler, priority, 0.0, cpuAffinity, nullptr, name) {}
  ~WakeActivity() override { stop(); }  // before RTT::Activity's destructor: our loop() leaves first

  /// The next time the thread wakes by itself for an update step (max(): none; a time passed:
  /// at once, without sleeping). Any thread; typically the component's updateHook().
  void wakeAt(Clock::time_point deadline) noexcept {
    deadline_.store(deadline.time_since_epoch().count(), std::memory_order_seq_cst);
    wake_.notify();  // a sleeping thread takes the new deadline (no system call when awake)
  }

  bool start() override {
    if (isActive()) return false;
    break_.store(false);
    trigger_.store(false);
    timeout_.store(false);
    deadline_.store(kNone);
    return RTT::Activity::start();
  }

  bool trigger() override { return post(trigger_); }
  bool timeout() override { return post(timeout_); }

  bool breakLoop() override {
    break_.store(true, std::memory_order_seq_cst);
    wake_.notify();
    return true;
  }

  void loop() override {
    for (;;) {
      const std::uint32_t armed = wake_.arm();
      if (break_.exchange(false, std::memory_order_seq_cst)) return;
      const bool triggered = trigger_.exchange(false, std::memory_order_seq_cst);
      bool timedOut = timeout_.exchange(false, std::memory_order_seq_cst);
      if (!triggered && !timedOut) {
        Clock::rep at = deadline_.load(std::memory_order_seq_cst);
        const Clock::time_point deadline = at == kNone ? Clock::time_point::max() : Clock::time_point(Clock::duration(at));
        if (deadline == Clock::time_point::max() || Clock::now() < deadline) {
          wake_.wait(armed, deadline, std::uint64_t{0});  // only notify() or the deadline wakes it
          continue;
        }
        // passed: cleared, unless the deadline changed meanwhile (then it is looked at again)
        if (!deadline_.compare_exchange_strong(at, kNone, std::memory_order_seq_cst)) continue;
        timedOut = true;
      }
      step();
      work(timedOut ? RTT::base::RunnableInterface::TimeOut : RTT::base::RunnableInterface::Trigger);
    }
  }

 private:
  static constexpr Clock::rep kNone = Clock::time_point::max().time_since_epoch().count();

  bool post(std::atomic<bool>& flag) noexcept {
    if (!isActive()) return false;
    flag.store(true, std::memory_order_seq_cst);
    wake_.notify();
    return true;
  }

  earl::Wake wake_;
  std::atomic<bool> break_{false};
  std::atomic<bool> trigger_{false};
  std::atomic<bool> timeout_{false};
  std::atomic<Clock::rep> deadline_{kNone};
};

}  // namespace earl::rtt
